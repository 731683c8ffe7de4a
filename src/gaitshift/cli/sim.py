"""``gaitshift simulate``: plan a scenario and run it closed-loop on the simulated G1."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Optional

import typer

from ..errors import InputError
from .app import app


@app.command("simulate")
def simulate_cmd(
    scenario: str = typer.Argument(..., help="Built-in scenario name or YAML path."),
    out: Path = typer.Option(..., "--out", help="Simulation log (.npz)."),
    video: Optional[Path] = typer.Option(None, "--video", help="Write an MP4 video (needs MUJOCO_GL=egl)."),
    viewer: bool = typer.Option(False, "--viewer", help="Open the MuJoCo viewer (needs a display)."),
    push: float = typer.Option(0.0, "--push", help="Lateral impulse, N s, at mid-stance of steps 4 and 8."),
    figures: Optional[Path] = typer.Option(None, "--figures", help="Folder for the figures (PNG)."),
    control_period: float = typer.Option(0.002, "--control-period", help="Control period = time step, s."),
    as_json: bool = typer.Option(False, "--json", help="Print the metrics as JSON instead of a table."),
) -> None:
    """Simulate SCENARIO on the G1 (MuJoCo) and print the summary metrics."""
    from .. import plan
    from ..scenario import load_scenario
    from ..sim.loop import OnlineReplanner, SimOptions, mid_stance_pushes, simulate
    from ..sim.metrics import format_metrics

    if out.suffix.lower() != ".npz":
        raise InputError("--out", str(out), "a file ending in .npz")
    if video is not None and video.suffix.lower() != ".mp4":
        raise InputError("--video", str(video), "a file ending in .mp4")
    if push < 0:
        raise InputError("--push", push, "an impulse >= 0 N s")
    sc = load_scenario(scenario)
    replanner = OnlineReplanner(sc) if sc.planner == "vhip" else None
    traj = replanner.trajectory if replanner else plan(sc)
    pushes = mid_stance_pushes(traj, push) if push > 0 else ()
    opts = SimOptions(control_period=control_period, pushes=pushes,
                      video=str(video) if video else None, viewer=viewer)
    result = simulate(traj, opts, replanner=replanner)
    if replanner is not None:
        traj = replanner.trajectory  # the plan as finally re-planned from the measured states
    result.save(out)
    if figures is not None:
        from ..plots.sim import plot_all

        for p in plot_all(result, traj, figures):
            typer.echo(f"wrote {p}")
    if as_json:
        from ..sim.loop import finite_json

        typer.echo(json.dumps(finite_json(result.metrics), allow_nan=False))
    else:
        how = f", {result.meta['replans']} re-plans from the measured CoM" if replanner else ""
        typer.echo(f"scenario {sc.name}: {len(traj.footsteps) - 2} footholds, {traj.t[-1]:.2f} s planned{how}")
        typer.echo(format_metrics(result.metrics))
    typer.echo(f"wrote {out}" + (f", {video}" if video else ""))


#: Scenario simulated by ``gaitshift demo`` (falls back to g1-walk when it is not installed).
DEMO_SIM_SCENARIO = "g1-walk-run-walk"


def demo_simulation(out: Path, video: bool) -> None:
    """``make demo`` step: simulate walk-run-walk on the G1; video, figures and summary into ``out``."""
    from .. import plan
    from ..scenario import builtin_names, load_scenario
    from ..sim.loop import SimOptions, simulate
    from ..sim.metrics import format_metrics
    from ..plots.sim import plot_all
    from ..io import atomic_path

    name = DEMO_SIM_SCENARIO if DEMO_SIM_SCENARIO in builtin_names() else "g1-walk"
    traj = plan(load_scenario(name))
    vid = out / "sim.mp4" if video else None
    try:
        result = simulate(traj, SimOptions(video=str(vid) if vid else None))
    except InputError as exc:  # no OpenGL context: simulate without the video
        typer.echo(f"no video ({exc}); simulating without it", err=True)
        vid = None
        result = simulate(traj)
    result.save(out / "sim.npz")
    for p in plot_all(result, traj, out):
        typer.echo(f"wrote {p}")
    table = f"closed-loop simulation of {name} on the Unitree G1\n" + format_metrics(result.metrics)
    with atomic_path(out / "sim_summary.txt") as tmp:
        tmp.write_text(table + "\n")
    typer.echo(table)
    typer.echo(f"wrote {out / 'sim.npz'}" + (f", {vid}" if vid else "") + f", {out / 'sim_summary.txt'}")
