"""Unitree low-level protocol commands: ``gaitshift dds robot ROBOT`` (the MuJoCo world behind the protocol) and
``gaitshift dds control SCENARIO`` (the brain: the controller over the protocol, behind the safety machine)."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import typer

from gaitshift.cli.app import app, out_file

dds_app = typer.Typer(help="Unitree's low-level DDS protocol (hg messages, the G1).", no_args_is_help=True)
app.add_typer(dds_app, name="dds")


@dds_app.command("robot")
def dds_robot_cmd(
    robot: str = typer.Argument("g1", help="Built-in robot name or YAML whose motors are the hg slots (the G1)."),
    domain: int = typer.Option(1, "--domain", help="DDS domain id (1: simulation; 0 is the real robot's network)."),
    iface: str = typer.Option("lo", "--iface", help="Network interface (lo: nothing leaves the machine)."),
    duration: float | None = typer.Option(None, "--duration", help="Simulated seconds to run (default: until ^C)."),
    summary: Path | None = typer.Option(None, "--summary", help="JSON summary, written on exit and on SIGINT/SIGTERM."),
    lockstep: bool = typer.Option(False, "--lockstep", help="Step only when a command for the last state came."),
    damping_after: float = typer.Option(0.1, "--damping-after", help="s without a command before damping."),
    damping_kd: float = typer.Option(2.0, "--damping-kd", help="Damping gain, N m s/rad (kp = 0)."),
    mode_machine: int = typer.Option(0, "--mode-machine", help="The hardware variant reported in LowState_."),
    noise: str = typer.Option("none", "--noise", help="Sensor noise profile: none, typical, rl-peer."),
) -> None:
    """Run ROBOT in gaitshift's MuJoCo world behind the protocol: rt/lowstate out every control period,
    rt/lowcmd in (bad CRCs dropped and counted), tau + kp (q_des - q) + kd (dq_des - dq) per motor."""
    from gaitshift.common.atomic import atomic_path
    from gaitshift.common.jsonsafe import finite_json
    from gaitshift.dds.robot import RobotOptions, run_robot

    if summary is not None:
        out_file(summary, "--summary", (".json",))
    opts = RobotOptions(
        robot=robot,
        domain=domain,
        iface=iface,
        duration=duration,
        lockstep=lockstep,
        damping_after=damping_after,
        damping_kd=damping_kd,
        mode_machine=mode_machine,
        noise=noise,
    )
    mode = "lockstep" if lockstep else "real time"
    typer.echo(f"{robot} on DDS domain {domain} over {iface} ({mode}): rt/lowstate out, rt/lowcmd in", err=True)
    result = run_robot(opts)
    if summary is not None:
        with atomic_path(summary, "--summary") as tmp:
            tmp.write_text(json.dumps(finite_json(result.as_dict()), indent=2, allow_nan=False))
    fall = f"fell at {result.fall_time:.3f} s ({result.fall_reason})" if result.fell else "did not fall"
    typer.echo(
        f"{result.sim_time:.3f} s simulated in {result.wall_time:.2f} s, {fall}, moved {result.distance:.3f} m; "
        f"{result.states_published} states out, {result.packets_received} commands in, {result.packets_dropped} "
        f"dropped ({result.crc_rejects} bad CRC), {result.damping_ticks} ticks damping, {result.late_ticks} late"
    )


@dds_app.command("control")
def dds_control_cmd(
    scenario: str = typer.Argument(..., help="Built-in scenario name or YAML (a short one for a first run)."),
    robot: str | None = typer.Option(None, "--robot", help="Robot name or YAML (default: the scenario's)."),
    domain: int = typer.Option(
        1, "--domain", help="DDS domain id (1: simulation; 0, a real robot, needs --real-robot)."
    ),
    iface: str = typer.Option("lo", "--iface", help="Network interface (lo: nothing leaves the machine)."),
    as_json: bool = typer.Option(False, "--json", help="Print the run's summary as JSON (alone on stdout)."),
    lockstep: bool = typer.Option(False, "--lockstep", help="Tick once per new state instead of every 2 ms."),
    state_timeout: float = typer.Option(10.0, "--state-timeout", help="s to wait for the robot's first state."),
    real_robot: bool = typer.Option(False, "--real-robot", help="Allow domain 0; refuse unless the robot damps."),
    stale_limit: float = typer.Option(0.02, "--stale-limit", help="s: an older state is a fault (damping)."),
    damping_time: float = typer.Option(0.1, "--damping-time", help="s of damping before the stand-up."),
    standup_time: float = typer.Option(2.0, "--standup-time", help="s of the stand-up to the start pose."),
    damping_kd: float = typer.Option(2.0, "--damping-kd", help="Damping gain, N m s/rad (kp = 0)."),
    tilt_limit: float = typer.Option(0.6, "--tilt-limit", help="rad of pelvis tilt taken as a fall."),
    final_damping: float = typer.Option(0.2, "--final-damping", help="s of damping written before exiting."),
    contact: str = typer.Option("torque", "--contact", help="Contact detection: torque (no foot force) or force."),
    replan: str = typer.Option(
        "process", "--replan", help="Where the plan is re-planned: process (off the tick), thread or inline."
    ),
    warm: bool = typer.Option(
        True, "--warm-up/--no-warm-up", help="Tick a throwaway controller first (fast 1st ticks)."
    ),
) -> None:
    """Run SCENARIO's controller over the protocol: rt/lowstate in, rt/lowcmd out, behind the safety
    machine (damping, stand-up, locomotion, stop, damping; any fault: damping). Exit 0 when the plan
    ended, 1 on a fault or when no robot answers."""
    from gaitshift.common.jsonsafe import finite_json
    from gaitshift.dds.brain import BrainOptions, build_controller, run_brain
    from gaitshift.dds.warmup import warm_up

    opts = BrainOptions(
        scenario=scenario,
        robot=robot,
        domain=domain,
        iface=iface,
        lockstep=lockstep,
        state_timeout=state_timeout,
        real_robot=real_robot,
        stale=stale_limit,
        damping_time=damping_time,
        standup_time=standup_time,
        damping_kd=damping_kd,
        tilt=tilt_limit,
        final_damping=final_damping,
        contact=contact,
        replan=replan,
    )
    mode = "lockstep" if lockstep else "real time"
    ctrl = build_controller(opts)
    if warm:
        # the throwaway re-plans inline: a worker of its own would only cost a process start
        typer.echo(f"warm-up: {warm_up(build_controller(replace(opts, replan='inline'))):.2f} s", err=True)
    typer.echo(
        f"{scenario} on DDS domain {domain} over {iface} ({mode}): waiting up to {state_timeout:g} s for rt/lowstate",
        err=True,
    )
    s = run_brain(opts, ctrl=ctrl)
    if as_json:
        typer.echo(json.dumps(finite_json(s.as_dict()), indent=2, allow_nan=False))
    if s.exit_code:
        typer.echo(f"gaitshift: {s.phase}: {s.reason}", err=True)
    else:
        typer.echo(
            f"{s.reason}: {s.ticks} ticks ({s.locomotion_ticks} of the controller), tick p50/p99/p99.9 "
            f"{s.tick_p50_ms:.2f}/{s.tick_p99_ms:.2f}/{s.tick_p999_ms:.2f} ms, {s.missed_deadlines} missed deadlines; "
            "the robot damps",
            err=True,
        )
    raise typer.Exit(s.exit_code)
