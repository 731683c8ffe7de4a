"""Core commands: stiffness, scenarios, plan, plot, demo."""

from __future__ import annotations

import json
from pathlib import Path

import typer

from ..scenario import builtin_names, load_scenario
from ..trajectory import Trajectory, check_suffix
from .app import app


@app.command("stiffness")
def stiffness_cmd(
    height: float = typer.Option(..., help="Nominal CoM height h, m."),
    single_support: float = typer.Option(..., help="Single-support duration tau_SS, s."),
    double_support: float = typer.Option(..., help="Double-support duration tau_DS, s."),
    flight: float = typer.Option(..., help="Flight duration tau_F, s."),
    gravity: float = typer.Option(9.81, help="Gravity g, m/s^2."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object with T_w, T_r, v_r, T_t0, T_t1."),
) -> None:
    """Stiffness T of the time-varying LIPM for walking, running and transitions (paper 001 §III)."""
    from ..stiffness import stiffness

    k = stiffness(height, single_support, double_support, flight, gravity)
    if as_json:
        typer.echo(json.dumps(k.as_dict()))
    else:
        for key, val in k.as_dict().items():
            unit = "m/s" if key == "v_r" else "s"
            typer.echo(f"{key:5s} = {val:.6f} {unit}")


@app.command("scenarios")
def scenarios_cmd() -> None:
    """List the built-in scenarios."""
    for name in builtin_names():
        sc = load_scenario(name)
        typer.echo(f"{name:36s} [{sc.planner}] {sc.description}")


@app.command("plan")
def plan_cmd(
    scenario: str = typer.Argument(..., help="Built-in scenario name or YAML path."),
    out: Path = typer.Option(..., "--out", help="Output file: .npz, .csv or .json."),
) -> None:
    """Plan a scenario and write the trajectory file."""
    from .. import plan

    check_suffix(out, "--out")  # before planning: fail fast, write nothing
    sc = load_scenario(scenario)
    traj = plan(sc)
    traj.save(out)
    m = traj.meta
    typer.echo(f"planned {sc.name} with {m['planner']}: {traj.t[-1]:.3f} s, {len(traj)} samples at "
               f"dt={traj.dt:g} s, {len(traj.footsteps)} footholds")
    if "plan_time_s" in m:
        typer.echo(f"solve: {m.get('iterations', '?')} Gauss-Newton iterations, {m['plan_time_s'] * 1e3:.2f} ms")
    typer.echo(f"wrote {out}")


@app.command("plot")
def plot_cmd(
    file: Path = typer.Argument(..., help="Trajectory file written by `gaitshift plan`."),
    out: Path = typer.Option(..., "--out", help="Folder for the PNG figures."),
) -> None:
    """Write the figures of a planned trajectory as PNGs."""
    traj = Trajectory.load(file)
    paths = _figures(traj, out)
    for p in paths:
        typer.echo(f"wrote {p}")


def _figures(traj: Trajectory, out: Path) -> list[Path]:
    if traj.meta["planner"] == "vhip":
        from ..plots.online import write_figures
    else:
        from ..plots.tvlip import write_figures  # type: ignore[no-redef]
    return write_figures(traj, out)


DEMO_SCENARIO = "paper001-table2-walk-run-walk"


@app.command("demo")
def demo_cmd(
    out: Path = typer.Option(Path("out/demo"), "--out", help="Output folder."),
    video: bool = typer.Option(True, help="Render the whole-body and simulation videos (slow: software GL)."),
) -> None:
    """The main job: plan walk-run-walk (paper 001), write its file and figures, render the G1's
    whole-body motion, and run it closed-loop on the G1 in MuJoCo (video, figures, summary)."""
    from .. import plan

    out.mkdir(parents=True, exist_ok=True)
    sc = load_scenario(DEMO_SCENARIO)
    traj = plan(sc)
    path = traj.save(out / "walk_run_walk.npz")
    typer.echo(f"planned {DEMO_SCENARIO}: {traj.t[-1]:.2f} s, {len(traj.footsteps)} footholds -> {path}")
    for p in _figures(traj, out):
        typer.echo(f"wrote {p}")
    if video:
        from ..robot.render import animate

        path, joints = animate("g1-walk-run-walk", out / "g1_walk_run_walk.mp4", robot="g1")
        typer.echo(f"whole-body IK on the G1 ({len(joints.t)} samples) and video -> {path}")
    from .sim import demo_simulation

    demo_simulation(out, video)


@app.command("check")
def check_cmd(
    file: Path = typer.Argument(..., help="Trajectory file (.npz, .csv, .json)."),
    as_json: bool = typer.Option(False, "--json", help="Print the report as JSON."),
) -> None:
    """Verify a trajectory file's physics: ZMP identity, flight, continuity, support polygon, rest.

    Exits 0 when every error is within its limit, 1 otherwise.
    """
    from ..analysis import check_limits, physics_report

    traj = Trajectory.load(file)
    rep = physics_report(traj)
    limits = check_limits(traj.dt)
    ok = {k: rep[k] <= lim for k, lim in limits.items()}
    ok["min_vertical_force"] = rep["min_vertical_force"] > 0
    if as_json:
        typer.echo(json.dumps({"report": rep, "pass": ok, "limits": limits}))
    else:
        for k, val in rep.items():
            lim = limits.get(k)
            bound = f"<= {lim:g}" if lim is not None else "> 0"
            typer.echo(f"{'ok  ' if ok[k] else 'FAIL'} {k:20s} {val:.3e}  ({bound})")
    if not all(ok.values()):
        raise typer.Exit(1)
