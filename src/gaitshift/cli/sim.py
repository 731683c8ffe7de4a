"""``gaitshift simulate``: plan a scenario and run it closed-loop on a simulated robot (``--robot``)."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import typer

from gaitshift.cli.app import app, flags_named, out_file, out_folder
from gaitshift.cli.web import web_port_option, web_view
from gaitshift.errors import InputError


@app.command("simulate")
def simulate_cmd(
    scenario: str = typer.Argument(..., help="Built-in scenario name or YAML path."),
    out: Path = typer.Option(..., "--out", help="Simulation log (.npz)."),
    video: Path | None = typer.Option(None, "--video", help="Write an MP4 video (needs MUJOCO_GL=egl)."),
    viewer: bool = typer.Option(False, "--viewer", help="Open the MuJoCo viewer (needs a display)."),
    push: list[str] = typer.Option(
        [],
        "--push",
        help="Push (repeatable): J = lateral impulses of J N s at mid-stance of steps 4 (+y) and 8 (-y); or"
        " T,JX,JY[,JZ[,DURATION]] = impulse (N s, world frame) from plan time T s over DURATION s (0.1).",
    ),
    bump: list[str] = typer.Option(
        [], "--bump", help="Bump on the floor (repeatable): X,HEIGHT[,LENGTH] m (box from X to X+LENGTH; 0.2)."
    ),
    mass_scale: float | None = typer.Option(
        None, "--mass-scale", help="Factor on the simulated robot's masses; the controller keeps the nominal (1)."
    ),
    joint_vel_noise: float | None = typer.Option(
        None, "--joint-vel-noise", help="Extra uniform joint-velocity sensor noise, rad/s half-width (0)."
    ),
    com_offset: str | None = typer.Option(
        None, "--com-offset", help="X,Y,Z m: the simulated base's centre of mass moved (base frame; 0,0,0)."
    ),
    motor_strength: float | None = typer.Option(
        None, "--motor-strength", help="Factor on the simulated motors' torque and torque limit (1)."
    ),
    figures: Path | None = typer.Option(None, "--figures", help="Folder for the figures (PNG)."),
    control_period: float = typer.Option(0.002, "--control-period", help="Control period = time step, s."),
    as_json: bool = typer.Option(False, "--json", help="Print the metrics as JSON (alone on stdout)."),
    robot: str | None = typer.Option(
        None, "--robot", help="Built-in robot name or robot YAML path (default: the scenario's robot, else g1)."
    ),
    state: str | None = typer.Option(
        None, "--state", help="What the controller sees: estimated (default; oracle without an IMU) or oracle."
    ),
    noise: str | None = typer.Option(None, "--noise", help="Sensor noise: none, typical (default) or rl-peer."),
    noise_scale: float | None = typer.Option(None, "--noise-scale", help="Factor on every sensor noise (1)."),
    latency: int | None = typer.Option(
        None, "--latency", help="Loop latency = actuation delay, ticks (sensing + actuation, one setting; 0)."
    ),
    friction: float | None = typer.Option(None, "--friction", help="The floor's friction coefficient."),
    contact: str | None = typer.Option(
        None,
        "--contact",
        help="Contact sensing: torque (motor torques) or force (sole sensors); default: the robot YAML's.",
    ),
    seed: int | None = typer.Option(None, "--seed", help="Seed of every random draw of the run (0)."),
    terrain: str | None = typer.Option(
        None,
        "--terrain",
        help="What the planner is told of the terrain (the world keeps it): known (default), blind (flat"
        " ground) or perceived (footholds from the robot's elevation map; TV-LIPM scenarios).",
    ),
    rerun: Path | None = typer.Option(None, "--rerun", help="Also write a Rerun recording (.rrd; needs rerun-sdk)."),
    video_size: str | None = typer.Option(None, "--video-size", help="Video size WIDTHxHEIGHT, pixels (1280x720)."),
    video_fps: int | None = typer.Option(None, "--video-fps", help="Video frame rate, Hz (30)."),
    web: bool = typer.Option(False, "--web", help="Serve a live view in the browser (paced to the wall clock)."),
    web_port: int = web_port_option(),
) -> None:
    """Simulate SCENARIO on a robot (MuJoCo) and print the summary metrics; exit 1 when it falls.

    The robot is the scenario's ``robot``, else --robot, else g1; a --robot other than the scenario's
    own robot is an error (scale the scenario first: `gaitshift scale`). Before the run, the robot's
    joint-speed limits are checked against the plan's whole-body motion (IK)."""
    from gaitshift.sim.scenario_run import run_prepared

    sensing: dict[str, Any] = {"state": state, "noise": noise, "noise_scale": noise_scale, "latency": latency}
    sensing |= {"friction": friction, "mass_scale": mass_scale, "joint_vel_noise": joint_vel_noise, "contact": contact}
    sensing |= {"com_offset": numbers("--com-offset", com_offset, 3), "motor_strength": motor_strength}
    flags = sensing_flags(out, video, None, rerun, seed=seed, video_size=video_size, video_fps=video_fps, **sensing)
    pushes_given, bumps = perturbation_flags(push, bump)
    if figures is not None:
        figures_folder(figures)
    prepared = checked_plan(scenario, robot, control_period, terrain)
    sc, cfg, driver, traj = prepared
    given = flags | ({"bumps": bumps} if bumps else {}) | ({"pushes": pushes_given} if push else {})
    given |= {"control_period": control_period, "video": str(video) if video else None, "viewer": viewer or None}
    with web_view(web, web_port, lambda: driver.trajectory if driver else traj, as_json, realtime=True) as views:
        run = run_prepared(prepared, hooks=views, **given)
    report(run.result, run.trajectory, cfg, driver, ReportFiles(out, video, rerun, figures), as_json, sc.name)


def checked_plan(scenario: str, robot: str | None, control_period: float, terrain: str | None) -> Any:
    """What :func:`gaitshift.control.drivers.prepare` returns, the control period checked first (a
    period of 0 ended in ZeroDivisionError) and, for a plan run as planned, the robot's joint-speed
    limits checked against its whole-body motion (IK)."""
    from gaitshift.control.drivers import prepare
    from gaitshift.robots.model import check_period

    with flags_named({"control_period": "--control-period"}):
        check_period(control_period)
        prepared = prepare(scenario, robot, control_period, terrain)
    _, cfg, driver, traj = prepared
    if driver is None:
        from gaitshift.wholebody.checks import check_joint_speeds

        check_joint_speeds(cfg, traj)
    return prepared


def numbers(flag: str, text: str | None, n: int) -> tuple[float, ...] | None:
    """``text`` as ``n`` comma-separated finite numbers (None: not given); one line naming ``flag``."""
    if text is None:
        return None
    parts = text.split(",")
    try:
        vals = tuple(float(x) for x in parts)
    except ValueError:
        vals = ()
    if len(vals) != n or not all(math.isfinite(v) for v in vals):
        raise InputError(flag, text, f"{n} comma-separated numbers")
    return vals


def figures_folder(path: Path) -> Path:
    """``--figures``: a folder (made when missing), checked before the run (a file there, a name too long,
    no writable location: one line)."""
    return out_folder(path, "--figures")


@dataclass(frozen=True)
class ReportFiles:
    """Where ``simulate`` writes: the log (.npz), the video (.mp4), the Rerun recording (.rrd) and the
    figures folder (None: not asked for)."""

    out: Path
    video: Path | None = None
    rerun: Path | None = None
    figures: Path | None = None


def report(result: Any, traj: Any, cfg: Any, driver: Any, files: ReportFiles, as_json: bool, name: str) -> None:
    """Save the run and print its metrics (JSON alone on stdout with ``as_json``); exit 1 on a fall."""
    from gaitshift.common.jsonsafe import finite_json
    from gaitshift.export.sim_recording import record_simulation
    from gaitshift.sim.metrics import format_metrics

    result.save(files.out)
    if files.rerun is not None:
        record_simulation(result, traj, cfg, files.rerun)
    if files.figures is not None:
        from gaitshift.plots.sim import plot_all

        for p in plot_all(result, traj, files.figures):
            typer.echo(f"wrote {p}", err=as_json)
    if as_json:
        typer.echo(json.dumps(finite_json(result.metrics), allow_nan=False))
    else:
        typer.echo(_summary_line(name, cfg.name, traj, driver, result.meta))
        typer.echo(format_metrics(result.metrics))
    written = [str(f) for f in (files.out, files.video, files.rerun) if f is not None]
    typer.echo("wrote " + ", ".join(written), err=as_json)
    if result.fell:
        raise typer.Exit(1)


def perturbation_flags(push: list[str], bump: list[str]) -> tuple[list[Any], tuple[Any, ...]]:
    """The parsed ``--push`` values (:func:`gaitshift.sim.pushes.parse_push`: a Push, or the legacy
    lateral impulse as a float) and ``--bump`` values (:class:`gaitshift.sim.bumps.Bump`)."""
    from gaitshift.sim.bumps import parse_bump
    from gaitshift.sim.pushes import parse_push

    return [parse_push(p) for p in push], tuple(parse_bump(b) for b in bump)


def sensing_flags(
    out: Path, video: Path | None, push: float | None, rerun: Path | None = None, **given: Any
) -> dict[str, Any]:
    """Check ``simulate``'s file and push flags and return the given sensing flags as SimOptions fields.

    A bad sensing value is reported under its flag's name (``--noise-scale``), not the option's."""
    from gaitshift.sim.loop import SimOptions

    out_file(out, "--out", (".npz",))
    if video is not None:
        out_file(video, "--video", (".mp4",))
    if push is not None and push < 0:
        raise InputError("--push", push, "an impulse >= 0 N s")
    if rerun is not None:
        from gaitshift.export.recording import check_rrd

        check_rrd(out_file(rerun, "--rerun", (".rrd",)))
    flags = {k: v for k, v in given.items() if v is not None}
    if "video_size" in flags:
        from gaitshift.sim.video import parse_video_size

        flags["video_size"] = parse_video_size(flags["video_size"])
    try:
        SimOptions(**flags)
    except InputError as exc:  # name the flag, not the option
        raise InputError("--" + exc.field.replace("_", "-"), exc.value, exc.allowed) from None
    return flags


def _summary_line(scenario: str, robot: str, traj: Any, driver: Any, meta: dict[str, Any]) -> str:
    """The first line of the text report: scenario, robot, footholds, planned duration and feedback."""
    how = ""
    if driver is not None:
        how = (
            ", capture-point step feedback from the measured CoM"
            if driver.step_feedback
            else f", {meta['replans']} re-plans from the measured CoM"
        )
    return f"scenario {scenario} on {robot}: {len(traj.footsteps) - 2} footholds, {traj.t[-1]:.2f} s planned{how}"


#: Scenario simulated by ``gaitshift demo`` (falls back to g1-walk when it is not installed).
DEMO_SIM_SCENARIO = "g1-walk-run-walk"


def demo_simulation(out: Path, video: bool) -> None:
    """``make demo`` step: simulate walk-run-walk on the G1; video, figures and summary into ``out``."""
    from gaitshift.common.atomic import atomic_path
    from gaitshift.plots.sim import plot_all
    from gaitshift.scenario import builtin_names
    from gaitshift.sim.metrics import format_metrics
    from gaitshift.sim.scenario_run import simulate_scenario

    name = DEMO_SIM_SCENARIO if DEMO_SIM_SCENARIO in builtin_names() else "g1-walk"
    vid = out / "sim.mp4" if video else None
    try:
        run = simulate_scenario(name, video=str(vid) if vid else None)
    except InputError as exc:  # no OpenGL context: simulate without the video
        typer.echo(f"no video ({exc}); simulating without it", err=True)
        vid = None
        run = simulate_scenario(name)
    result, traj = run.result, run.trajectory
    result.save(out / "sim.npz")
    for p in plot_all(result, traj, out):
        typer.echo(f"wrote {p}")
    table = f"closed-loop simulation of {name} on the Unitree G1\n" + format_metrics(result.metrics)
    with atomic_path(out / "sim_summary.txt") as tmp:
        tmp.write_text(table + "\n")
    typer.echo(table)
    typer.echo(f"wrote {out / 'sim.npz'}" + (f", {vid}" if vid else "") + f", {out / 'sim_summary.txt'}")
