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
    from ..sim.loop import SimOptions, mid_stance_pushes, simulate
    from ..sim.metrics import format_metrics

    if out.suffix.lower() != ".npz":
        raise InputError("--out", str(out), "a file ending in .npz")
    if video is not None and video.suffix.lower() != ".mp4":
        raise InputError("--video", str(video), "a file ending in .mp4")
    if push < 0:
        raise InputError("--push", push, "an impulse >= 0 N s")
    sc = load_scenario(scenario)
    traj = plan(sc)
    pushes = mid_stance_pushes(traj, push) if push > 0 else ()
    opts = SimOptions(control_period=control_period, pushes=pushes,
                      video=str(video) if video else None, viewer=viewer)
    result = simulate(traj, opts)
    result.save(out)
    if figures is not None:
        from ..plots.sim import plot_all

        for p in plot_all(result, traj, figures):
            typer.echo(f"wrote {p}")
    if as_json:
        typer.echo(json.dumps(result.metrics, default=float))
    else:
        typer.echo(f"scenario {sc.name}: {len(traj.footsteps) - 2} footholds, {traj.t[-1]:.2f} s planned")
        typer.echo(format_metrics(result.metrics))
    typer.echo(f"wrote {out}" + (f", {video}" if video else ""))
