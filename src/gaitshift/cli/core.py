"""Core commands: stiffness, scenarios, plan, plot, demo."""

from __future__ import annotations

import importlib
import json
import math
from collections.abc import Callable
from pathlib import Path

import typer

from gaitshift.cli.app import app, number, out_file, out_folder
from gaitshift.errors import InputError
from gaitshift.scenario import builtin_names, load_scenario
from gaitshift.scenario.fields import COM_HEIGHT_RANGE, DURATION_RANGE, GRAVITY_RANGE
from gaitshift.trajectory.contract import Trajectory
from gaitshift.trajectory.formats import SUFFIXES


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
    from gaitshift.models.stiffness import stiffness

    number(height, "--height", *COM_HEIGHT_RANGE)
    for flag, value in (
        ("--single-support", single_support),
        ("--double-support", double_support),
        ("--flight", flight),
    ):
        number(value, flag, *DURATION_RANGE)
    number(gravity, "--gravity", *GRAVITY_RANGE)
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
    robot: str | None = typer.Option(None, "--robot", help="Robot (name or YAML) for a scenario naming none."),
    rerun: Path | None = typer.Option(None, "--rerun", help="Also write a Rerun recording (.rrd; needs rerun-sdk)."),
) -> None:
    """Plan a scenario and write the trajectory file."""
    from gaitshift import plan
    from gaitshift.api import with_robot

    out_file(out, "--out", SUFFIXES)  # before planning: fail fast, write nothing
    if rerun is not None:
        from gaitshift.export.recording import check_rrd

        check_rrd(out_file(rerun, "--rerun", (".rrd",)))
    sc, _ = with_robot(load_scenario(scenario), robot)
    traj = plan(sc)
    traj.save(out)
    m = traj.meta
    typer.echo(
        f"planned {sc.name} with {m['planner']}: {traj.t[-1]:.3f} s, {len(traj)} samples at "
        f"dt={traj.dt:g} s, {len(traj.footsteps)} footholds"
    )
    if "plan_time_s" in m:
        typer.echo(f"solve: {m.get('iterations', '?')} Gauss-Newton iterations, {m['plan_time_s'] * 1e3:.2f} ms")
    typer.echo(f"wrote {out}")
    if rerun is not None:
        from gaitshift.export.recording import record_plan

        logged = record_plan(traj, rerun)
        typer.echo(f"wrote {rerun} ({logged['bodies']} body frames{'; ' + logged['note'] if logged['note'] else ''})")


@app.command("plot")
def plot_cmd(
    file: Path = typer.Argument(
        ..., help="Trajectory file written by `gaitshift plan`, or a log of `gaitshift simulate --out`."
    ),
    out: Path = typer.Option(..., "--out", help="Folder for the PNG figures."),
) -> None:
    """Write the figures of a planned trajectory as PNGs; of a simulation log, the state estimate
    against the truth (sim_estimation.png)."""
    out_folder(out, "--out")
    from gaitshift.plots import estimation

    if estimation.is_simulation_log(file):
        arrays, metrics = estimation.read_estimation_log(file)
        paths = [estimation.plot_estimation(arrays, out / "sim_estimation.png", metrics)]
    else:
        paths = _figures(Trajectory.load(file), out, str(file))
    for p in paths:
        typer.echo(f"wrote {p}")


def _tvlip_meta(traj: Trajectory, source: str) -> None:
    """The TV-LIPM figures redraw paper 001's Figs. 5-7 from ``meta.height`` and ``meta.scenario``."""
    from pydantic import ValidationError

    from gaitshift.scenario.fields import input_error
    from gaitshift.scenario.tvlip import TvlipScenario

    height = traj.meta.get("height")
    lo, hi = COM_HEIGHT_RANGE
    if not (isinstance(height, int | float) and not isinstance(height, bool) and lo <= height <= hi):
        raise InputError(
            f"{source}: meta.height", height, f"the CoM height of the plan, a number in [{lo:g}, {hi:g}] m"
        )
    try:
        TvlipScenario.model_validate(traj.meta.get("scenario"))
    except ValidationError as exc:
        raise input_error(exc, TvlipScenario, prefix=f"{source}: meta.scenario.") from None


#: planner of a trajectory -> (module with ``write_figures(traj, out)``, check of the meta it draws from)
FIGURES: dict[str, tuple[str, Callable[[Trajectory, str], None] | None]] = {
    "tvlip": ("gaitshift.plots.tvlip", _tvlip_meta),
    "vhip": ("gaitshift.plots.vhip", None),
    "locomotion": ("gaitshift.plots.locomotion", None),
}


def _figures(traj: Trajectory, out: Path, source: str = "Trajectory") -> list[Path]:
    planner = traj.meta["planner"]
    if planner not in FIGURES:
        raise InputError(f"{source}: meta.planner", planner, "a planner with figures: " + ", ".join(FIGURES))
    module, check_meta = FIGURES[planner]
    if check_meta is not None:
        check_meta(traj, source)  # before the first figure is written
    write_figures: Callable[[Trajectory, Path], list[Path]] = importlib.import_module(module).write_figures
    return write_figures(traj, out)


DEMO_SCENARIO = "paper001-table2-walk-run-walk"


@app.command("demo")
def demo_cmd(
    out: Path = typer.Option(Path("out/demo"), "--out", help="Output folder."),
    video: bool = typer.Option(True, help="Render the whole-body and simulation videos (slow: software GL)."),
) -> None:
    """The main job: plan walk-run-walk (paper 001), write its file and figures, render the G1's
    whole-body motion, and run it closed-loop on the G1 in MuJoCo (video, figures, summary)."""
    from gaitshift import plan

    out_folder(out, "--out")
    out.mkdir(parents=True, exist_ok=True)
    sc = load_scenario(DEMO_SCENARIO)
    traj = plan(sc)
    path = traj.save(out / "walk_run_walk.npz")
    typer.echo(f"planned {DEMO_SCENARIO}: {traj.t[-1]:.2f} s, {len(traj.footsteps)} footholds -> {path}")
    for p in _figures(traj, out):
        typer.echo(f"wrote {p}")
    if video:
        from gaitshift.wholebody.render import animate

        path, joints = animate("g1-walk-run-walk", out / "g1_walk_run_walk.mp4", robot="g1")
        typer.echo(f"whole-body IK on the G1 ({len(joints.t)} samples) and video -> {path}")
    from gaitshift.cli.sim import demo_simulation

    demo_simulation(out, video)


@app.command("check")
def check_cmd(
    file: Path = typer.Argument(..., help="Trajectory file (.npz, .csv, .json)."),
    as_json: bool = typer.Option(False, "--json", help="Print the report as JSON."),
) -> None:
    """Verify a trajectory file's physics: ZMP identity, flight, continuity, support polygon, rest.

    Exits 0 when every error is within its limit, 1 otherwise. In --json, min_vertical_force is null
    when no sample is in support.
    """
    from gaitshift.analysis.physics import check_limits, physics_report

    traj = Trajectory.load(file)
    rep = physics_report(traj)
    limits = check_limits(traj.dt)
    ok = {k: rep[k] <= lim for k, lim in limits.items()}
    ok["min_vertical_force"] = rep["min_vertical_force"] > 0
    if as_json:
        finite = {k: (v if math.isfinite(v) else None) for k, v in rep.items()}
        typer.echo(json.dumps({"report": finite, "pass": ok, "limits": limits}, allow_nan=False))
    else:
        for k, val in rep.items():
            lim = limits.get(k)
            bound = f"<= {lim:g}" if lim is not None else "> 0"
            typer.echo(f"{'ok  ' if ok[k] else 'FAIL'} {k:20s} {val:.3e}  ({bound})")
    if not all(ok.values()):
        raise typer.Exit(1)
