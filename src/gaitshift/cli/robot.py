"""Whole-body commands: robots, wholebody (IK to joint trajectories), animate (MP4)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer

from gaitshift.cli.app import app, flags_named, out_file, out_folder
from gaitshift.errors import InputError

_ROBOT_HELP = (
    "Built-in robot name (g1, t1, h1, op3, berkeley) or robot YAML path (default: the robot the scenario "
    "or plan names, else g1)."
)
_SOURCE_HELP = "Trajectory file (.npz/.csv/.json from `gaitshift plan`) or a scenario (built-in name or YAML)."


@app.command("robots")
def robots_cmd(
    robots: list[str] | None = typer.Argument(
        None, help="Robots to describe (built-in names or robot YAML paths); default: every built-in robot."
    ),
) -> None:
    """List robots (the built-in ones, or those given) with the numbers read from their models."""
    from gaitshift.robots import builtin_robots, load_robot

    configs = [load_robot(name) for name in (robots or builtin_robots())]  # every one loads before any line
    for r in configs:
        typer.echo(
            f"{r.name:4s} {r.description or r.source}: {r.mass:.1f} kg, {len(r.joint_names)} joints, CoM height "
            f"{r.com_height:.3f} m, leg length {r.leg_length:.3f} m, soles {r.sole_size[0]:.3f} x "
            f"{r.sole_size[1]:.3f} m, IMU {_imu(r)}, {'foot force' if r.sensors.foot_force else 'no foot force'}"
        )


def _imu(robot: Any) -> str:
    """Where the robot's IMU is: its MJCF's site, or the body (and offset, m) the YAML mounts it on."""
    mount = robot.sensors.imu
    if mount.body is None:
        return f"site {mount.site}"
    return f"on {mount.body}" + ("" if not any(mount.pos) else " at [" + ", ".join(f"{x:g}" for x in mount.pos) + "]")


@app.command("wholebody")
def wholebody_cmd(
    file: str = typer.Argument(..., help=_SOURCE_HELP),
    robot: str | None = typer.Option(None, "--robot", help=_ROBOT_HELP),
    out: Path = typer.Option(..., "--out", help="Output .npz with t, qpos, qvel and meta (JSON)."),
    rate: float | None = typer.Option(None, "--rate", help="Output rate, Hz (1/(k dt)); default: plan step."),
) -> None:
    """Whole-body IK: joint trajectories that reproduce the planned CoM and sole poses."""
    from gaitshift.api import plan_robot
    from gaitshift.wholebody.ik import wholebody
    from gaitshift.wholebody.joints import load_plan

    out_file(out, "--out", (".npz",))
    traj = load_plan(file)
    joints = wholebody(traj, plan_robot(traj, robot), rate=rate)
    joints.save(out)
    ik = joints.meta["ik"]
    typer.echo(
        f"{joints.meta['robot']}: {len(joints.t)} samples over {joints.t[-1] - joints.t[0]:.3f} s; max "
        f"error CoM {ik['max_com_error_m'] * 1e3:.3f} mm, soles {ik['max_sole_position_error_m'] * 1e3:.3f} "
        f"mm / {ik['max_sole_orientation_error_rad']:.2e} rad; IK {ik['total_time_s']:.2f} s "
        f"({ik['time_per_sample_median_s'] * 1e3:.3f} ms/sample median)"
    )
    for task in ik.get("dropped_tasks", []):
        typer.echo(f"dropped task: {task} (the leg has no joint to roll its foot; the sole roll is not controlled)")
    typer.echo(f"wrote {out}")


@app.command("animate")
def animate_cmd(
    file: str = typer.Argument(..., help=_SOURCE_HELP),
    robot: str | None = typer.Option(None, "--robot", help=_ROBOT_HELP),
    out: Path = typer.Option(..., "--out", help="Output .mp4."),
    joints: Path | None = typer.Option(None, "--joints", help="Reuse joint trajectories from `gaitshift wholebody`."),
    rate: float = typer.Option(500.0, "--rate", help="IK rate, Hz (when --joints is not given)."),
    fps: float = typer.Option(30.0, "--fps", help="Video frame rate, Hz."),
    width: int = typer.Option(640, "--width", help="Video width, pixels (even)."),
    height: int = typer.Option(360, "--height", help="Video height, pixels (even)."),
) -> None:
    """Offscreen MP4 of the whole-body motion with the CoM, ZMP and footsteps drawn."""
    from gaitshift.api import plan_robot
    from gaitshift.wholebody.joints import JointTrajectory, load_plan
    from gaitshift.wholebody.render import animate

    out_file(out, "--out", (".mp4",))
    with flags_named({"file": "--joints"}):
        jt = JointTrajectory.load(joints) if joints is not None else None
    traj = load_plan(file)
    name = plan_robot(traj, robot)
    with flags_named({"rate": "--rate", "fps": "--fps", "size": "--width/--height"}):
        path, _ = animate(traj, out, robot=name, rate=rate, fps=fps, width=width, height=height, joints=jt)
    typer.echo(f"wrote {path}")


@app.command("scale")
def scale_cmd(
    scenario: str = typer.Argument(..., help="Scenario to scale (built-in name or YAML)."),
    robot: str = typer.Option("g1", "--robot", help="Built-in robot name or robot YAML path."),
    out: Path = typer.Option(..., "--out", help="Output scenario YAML."),
    time_scale: str = typer.Option(
        "keep", "--time-scale", help="keep: the scenario's durations; froude: durations x sqrt(lambda)."
    ),
) -> None:
    """Scale a paper scenario to a robot (CoM height, strides, feet; see docs/robot.md) and write it as YAML."""

    from gaitshift.common.atomic import atomic_path
    from gaitshift.scenario import load_scenario
    from gaitshift.wholebody.scaling import scaled_yaml

    out_file(out, "--out", (".yaml", ".yml"))
    sc = load_scenario(scenario)
    text, lam = scaled_yaml(sc, robot, out.parent, time_scale)
    with atomic_path(out) as tmp:
        tmp.write_text(text)
    typer.echo(f"scaled {sc.name} by {lam:.4f} for {robot} -> {out}")


robot_app = typer.Typer(
    help="Robot tools: check a robot (and a scenario on it) before simulating.", no_args_is_help=True
)
app.add_typer(robot_app, name="robot")


@robot_app.command("check")
def robot_check_cmd(
    robot: str = typer.Argument(..., help="Built-in robot name or robot YAML path."),
    scenario: str | None = typer.Argument(
        None, help="Scenario (built-in name or YAML) to check on the robot, as `gaitshift simulate` would run it."
    ),
) -> None:
    """Report, before any simulation, what will fail: sole frame, balance and static torque in the
    standing pose; with SCENARIO also reach, joint limits and joint speeds of its whole-body motion.

    One line per check; exits 1 when any line is a PROBLEM, 0 otherwise."""
    from gaitshift.robots import load_robot
    from gaitshift.wholebody.robot_check import check_plan_for, robot_check

    if scenario is None:
        cfg, traj = load_robot(robot), None
    else:
        cfg, traj = check_plan_for(scenario, robot)
    findings = robot_check(cfg, traj)
    for f in findings:
        typer.echo(f.line())
    problems = sum(not f.ok for f in findings)
    typer.echo(f"{cfg.name}: {problems} problem{'s' if problems != 1 else ''}")
    if problems:
        raise typer.Exit(1)


@robot_app.command("tune")
def robot_tune_cmd(
    robot: Path = typer.Argument(..., help="Robot YAML to tune."),
    out: Path = typer.Option(..., "--out", help="The tuned robot YAML (.yaml)."),
    report: Path | None = typer.Option(None, "--report", help="Markdown report (.md)."),
    work: Path = typer.Option(Path("tune-work"), "--work", help="Folder of the candidates and their runs."),
    seed: list[int] = typer.Option([0], "--seed", help="Seed of the runs (repeatable)."),
    workers: int | None = typer.Option(None, "--workers", help="Dask workers (default: every core)."),
) -> None:
    """Find a new robot's gait keys: derive them from the model, then run a small campaign of candidates
    (the G1's walk, run, walk-run-walk and tour scaled to the robot, on the estimate) and keep the one
    that falls least, comes closest to the flight it plans, and changes least (docs/robots.md, "Tune")."""
    from gaitshift.common.atomic import atomic_path
    from gaitshift.tuning.report import report as report_text
    from gaitshift.tuning.search import check_seeds, robot_yaml, tune

    out_file(out, "--out", (".yaml", ".yml"))
    if report is not None:
        out_file(report, "--report", (".md",))
    out_folder(work, "--work")
    if workers is not None and workers < 1:  # before any candidate is written into --work
        raise InputError("--workers", workers, "an integer >= 1")
    result = tune(robot, work, check_seeds(seed), workers)
    with atomic_path(out) as tmp:
        tmp.write_text(
            f"# tuned by gaitshift robot tune from {robot}\n"
            + robot_yaml(robot.read_text(), result.best.keys(), robot.resolve().parent)
        )
    if report is not None:
        with atomic_path(report) as tmp:
            tmp.write_text(report_text(result, str(robot)))
    falls = sum(bool(r["fell"]) for r in result.rows if Path(r["scenario"]).parent.name == result.best.name)
    typer.echo(f"tuned {robot} -> {out}: gait {result.best.keys()}, {falls} fall(s) in its runs")
