"""Unitree low-level protocol commands: ``gaitshift dds robot ROBOT`` (the MuJoCo world behind the protocol),
``gaitshift dds control SCENARIO`` (the brain: the controller over the protocol, behind the safety machine; live
commands from the topic, the browser page and the keyboard: :mod:`gaitshift.cli.dds_live`) and
``gaitshift dds cmd`` (a live velocity command to the brain on ``rt/gaitshift/cmd_vel``)."""

from __future__ import annotations

import json
import socket
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from gaitshift.cli.app import app, out_file
from gaitshift.cli.web import web_port_option
from gaitshift.errors import InputError, check_choice

if TYPE_CHECKING:
    from gaitshift.dds.brain_options import BrainOptions, BrainSummary


def network_interface(iface: str) -> str:
    """``--iface``: a network interface of this machine, checked before any DDS participant opens.

    Raises:
        InputError: naming ``--iface`` and the interfaces there are.
    """
    names = [name for _, name in socket.if_nameindex()]
    if iface not in names:
        raise InputError("--iface", iface, "a network interface of this machine: " + ", ".join(names))
    return iface


def record_path(record: Path | None) -> str | None:
    """``--record``: checked before any work (a ``.npz`` name, a place a file can be written); as a string."""
    return None if record is None else str(out_file(record, "--record", (".npz",)))


dds_app = typer.Typer(help="Unitree's low-level DDS protocol (hg messages, the G1).", no_args_is_help=True)
app.add_typer(dds_app, name="dds")


@dds_app.command("robot")
def dds_robot_cmd(
    robot: str = typer.Argument("g1", help="Built-in robot name or YAML whose motors are the hg slots (the G1)."),
    domain: int = typer.Option(1, "--domain", help="DDS domain id (1: simulation; 0 is the real robot's network)."),
    iface: str = typer.Option("lo", "--iface", help="Network interface (lo: nothing leaves the machine)."),
    duration: float | None = typer.Option(None, "--duration", help="Simulated seconds to run (default: until ^C)."),
    summary: Path | None = typer.Option(None, "--summary", help="JSON summary, written on exit and on SIGINT/SIGTERM."),
    lockstep: bool = typer.Option(False, "--lockstep", help="Step only when this tick's command came."),
    gantry: bool = typer.Option(
        True, "--gantry/--no-gantry", help="Real time: hold the world still until the first valid command."
    ),
    damping_after: float = typer.Option(0.1, "--damping-after", help="s without a command before damping."),
    damping_kd: float = typer.Option(2.0, "--damping-kd", help="Damping gain, N m s/rad (kp = 0)."),
    mode_machine: int = typer.Option(0, "--mode-machine", help="The hardware variant reported in LowState_."),
    noise: str = typer.Option("none", "--noise", help="Sensor noise profile: none, typical, rl-peer."),
    drop: float = typer.Option(0.0, "--drop", help="Link fault: probability that a state is lost, [0, 0.5]."),
    corrupt: float = typer.Option(0.0, "--corrupt", help="Link fault: probability of a state with a bad CRC."),
    delay_ms: float = typer.Option(0.0, "--delay-ms", help="Link fault: ms added to every state (at 2 ms ticks)."),
    jitter_ms: float = typer.Option(0.0, "--jitter-ms", help="Link fault: ms, uniform spread of the delay."),
    seed: int = typer.Option(0, "--seed", help="Seed of the sensor noise and the link's faults."),
    world: str | None = typer.Option(
        None, "--world", help="Scenario (name or YAML) whose terrain and floor friction build the world (flat)."
    ),
    rt_priority: int | None = typer.Option(
        None, "--rt-priority", help="Run the loop under SCHED_FIFO at this priority, 1-99 (needs root)."
    ),
    record: Path | None = typer.Option(
        None, "--record", help="A .npz of the run, a row per tick: the truth, the command applied (on exit)."
    ),
) -> None:
    """Run ROBOT in gaitshift's MuJoCo world behind the protocol: rt/lowstate out every control period,
    rt/lowcmd in (bad CRCs dropped and counted), tau + kp (q_des - q) + kd (dq_des - dq) per motor; with
    --drop, --corrupt, --delay-ms, --jitter-ms the link to the brain loses, corrupts and delays states."""
    from gaitshift.common.atomic import atomic_path
    from gaitshift.common.jsonsafe import finite_json
    from gaitshift.dds.link import LinkFaults
    from gaitshift.dds.robot import RobotOptions, run_robot
    from gaitshift.scenario.sim_settings import NOISE_PROFILES

    if summary is not None:
        out_file(summary, "--summary", (".json",))
    record_file = record_path(record)
    network_interface(iface)
    check_choice("--noise", noise, NOISE_PROFILES)
    faults = LinkFaults(drop, corrupt, delay_ms / 1e3, jitter_ms / 1e3, seed)
    opts = RobotOptions(
        robot=robot,
        domain=domain,
        iface=iface,
        duration=duration,
        lockstep=lockstep,
        gantry=gantry,
        damping_after=damping_after,
        damping_kd=damping_kd,
        mode_machine=mode_machine,
        noise=noise,
        faults=faults,
        world=world,
        rt_priority=rt_priority,
        record=record_file,
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
        f"dropped ({result.crc_rejects} bad CRC), {result.damping_ticks} ticks damping, "
        f"{result.held_ticks} held in the gantry, {result.late_ticks} late"
    )


@dds_app.command("control")
def dds_control_cmd(
    scenario: str = typer.Argument(..., help="Built-in scenario name or YAML (a short one for a first run)."),
    robot: str | None = typer.Option(None, "--robot", help="Robot name or YAML (default: the scenario's)."),
    domain: int = typer.Option(1, "--domain", help="DDS domain id (1: simulation; 0, a robot: --real-robot)."),
    iface: str = typer.Option("lo", "--iface", help="Network interface (lo: nothing leaves the machine)."),
    as_json: bool = typer.Option(False, "--json", help="Print the run's summary as JSON (alone on stdout)."),
    lockstep: bool = typer.Option(False, "--lockstep", help="Tick once per robot tick, on its clock."),
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
    warm: bool = typer.Option(True, "--warm-up/--no-warm-up", help="Tick a throwaway controller first."),
    hold: float | None = typer.Option(
        None, "--hold", help="s standing still after the stand-up (2): gyro calibration."
    ),
    calibrate: bool = typer.Option(True, "--calibrate/--no-calibrate", help="Calibrate the gyro from the hold."),
    cmd_topic: bool = typer.Option(
        False, "--cmd-topic", help="Take live velocity commands from rt/gaitshift/cmd_vel (a locomotion scenario)."
    ),
    diag_every: int = typer.Option(
        1, "--diag-every", help="Write the state estimate on rt/gaitshift/estimate every N ticks (0: never)."
    ),
    latency: int | None = typer.Option(None, "--latency", help="Ticks to predict across (0 lockstep, 1 real time)."),
    deadline: float = typer.Option(1.5, "--deadline", help="Real time: periods a tick waits for a new state."),
    rt_priority: int | None = typer.Option(None, "--rt-priority", help="SCHED_FIFO priority of the tick, 1-99."),
    known_floor: bool = typer.Option(
        False,
        "--known-floor/--unknown-floor",
        help="The robot stands on a flat floor (a scenario without terrain): its height corrects the estimate.",
    ),
    web: bool = typer.Option(False, "--web", help="A browser page: the robot as estimated, command sliders."),
    web_port: int = web_port_option(),
    teleop: bool = typer.Option(
        False, "--teleop", help="Steer with the keys (arrows/wasd speed, z/x turn, space stand, q stop): a terminal."
    ),
    record: Path | None = typer.Option(None, "--record", help="A .npz of the run: a row per tick (on exit)."),
) -> None:
    """Run SCENARIO's controller over the protocol (rt/lowstate in, rt/lowcmd out) behind the safety machine
    (damping, stand-up, locomotion, stop, damping; a fault: damping); live commands from rt/gaitshift/cmd_vel
    (--cmd-topic), the page (--web), the keys (--teleop). Exit 0: the plan ended; 1: a fault, no robot."""
    from gaitshift.cli.dds_live import check_live_flags
    from gaitshift.dds.brain import BrainOptions

    network_interface(iface)
    check_live_flags(scenario, cmd_topic, web_port, teleop)  # one line, exit 2, before anything is built
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
        hold=BrainOptions.hold if hold is None else hold,
        calibrate=calibrate,
        cmd_topic=cmd_topic,
        diag_every=diag_every,
        latency=latency,
        deadline=deadline,
        known_floor=known_floor,
        rt_priority=rt_priority,
        record=record_path(record),
    )
    _start_brain(opts, warm, as_json, (web, web_port), teleop)


def _start_brain(opts: BrainOptions, warm: bool, as_json: bool, web: tuple[bool, int], teleop: bool) -> None:
    """Build the controller, warm up, open the live inputs (``web`` = (--web, --web-port), ``teleop``),
    run the brain, report."""
    from gaitshift.cli.dds_live import live_inputs
    from gaitshift.dds.brain import run_brain
    from gaitshift.dds.brain_setup import build_controller
    from gaitshift.dds.cmdvel import live_limits
    from gaitshift.dds.warmup import warm_up

    ctrl = build_controller(opts)
    if opts.cmd_topic or teleop:
        live_limits(ctrl, opts.scenario)  # not a live plan: one line, exit 2, before any DDS traffic
    if warm:
        # the throwaway re-plans inline: a worker of its own would only cost a process start
        typer.echo(f"warm-up: {warm_up(build_controller(replace(opts, replan='inline'))):.2f} s", err=True)
    mode = "lockstep" if opts.lockstep else "real time"
    typer.echo(
        f"{opts.scenario} on DDS domain {opts.domain} over {opts.iface} ({mode}): waiting up to "
        f"{opts.state_timeout:g} s for rt/lowstate",
        err=True,
    )

    def say(line: str) -> None:
        typer.echo(line, err=True)

    with live_inputs(ctrl, opts.cmd_topic, web, teleop, say) as (queues, page):
        s = run_brain(opts, ctrl=ctrl, say=say, queues=queues, page=page)
    _report(s, as_json)
    raise typer.Exit(s.exit_code)


def _report(s: BrainSummary, as_json: bool) -> None:
    """The brain's summary: JSON on stdout with ``as_json``; one line on stderr."""
    from gaitshift.common.jsonsafe import finite_json

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


@dds_app.command("cmd")
def dds_cmd_cmd(
    vx: float = typer.Option(0.0, "--vx", help="Forward speed, m/s (heading frame)."),
    vy: float = typer.Option(0.0, "--vy", help="Sideways speed, m/s (heading frame, left positive)."),
    yaw_rate: float = typer.Option(0.0, "--yaw-rate", help="Turn rate, rad/s (counter-clockwise positive)."),
    stop: bool = typer.Option(False, "--stop", help="Ramp down, stand and end the brain's run."),
    domain: int = typer.Option(1, "--domain", help="DDS domain id of the brain."),
    iface: str = typer.Option("lo", "--iface", help="Network interface (lo: nothing leaves the machine)."),
    repeat: int = typer.Option(3, "--repeat", help="Times the command is written (the brain keeps the newest)."),
    wait: float = typer.Option(3.0, "--wait", help="s to wait for the brain's reader."),
    teleop: bool = typer.Option(
        False, "--teleop", help="Steer with the keys (arrows/wasd speed, z/x turn, space stand, q stop) instead."
    ),
) -> None:
    """Write one live velocity command on rt/gaitshift/cmd_vel (read by gaitshift dds control --cmd-topic),
    or with --teleop one per key press. Exit 1 when no brain's reader matched within --wait s."""
    import time

    from gaitshift.dds.cmdvel import publish
    from gaitshift.dds.own_messages import VelocityCommand_
    from gaitshift.dds.transport import check_domain, open_participant
    from gaitshift.errors import number_in

    for flag, value in (("--vx", vx), ("--vy", vy), ("--yaw-rate", yaw_rate)):
        number_in(flag, value, (-10.0, 10.0), "rad/s" if flag == "--yaw-rate" else "m/s")
    number_in("--repeat", repeat, (1, 1000))
    number_in("--wait", wait, (0.0, 600.0), "s")
    check_domain(domain)
    network_interface(iface)
    if teleop:
        _teleop(domain, iface)
        return
    now = time.time()
    msg = VelocityCommand_(seq=int(now * 1e3) & 0xFFFFFFFF, stamp=now, vx=vx, vy=vy, yaw_rate=yaw_rate, stop=int(stop))
    endpoint = open_participant(domain, iface)  # gaitshift's topic only: nothing of the protocol
    what = "stop" if stop else f"vx {vx:g} m/s, vy {vy:g} m/s, yaw_rate {yaw_rate:g} rad/s"
    if not publish(endpoint, msg, repeat=repeat, wait=wait):
        typer.echo(
            f"gaitshift: no reader of rt/gaitshift/cmd_vel on DDS domain {domain} over {iface} within "
            f"{wait:g} s: is gaitshift dds control --cmd-topic running?",
            err=True,
        )
        raise typer.Exit(1)
    typer.echo(f"sent {what} on rt/gaitshift/cmd_vel (DDS domain {domain} over {iface})", err=True)


def _teleop(domain: int, iface: str) -> None:
    """``gaitshift dds cmd --teleop``: key presses to rt/gaitshift/cmd_vel until q (the stop command)."""
    from gaitshift.cli.keys import require_terminal

    require_terminal("--teleop")
    _key_loop(domain, iface)


def _key_loop(domain: int, iface: str) -> None:
    import threading

    from gaitshift.cli.dds_live import KEYS_HELP
    from gaitshift.cli.keys import KeyReader, key_loop
    from gaitshift.dds.cmdvel import KeySteer, command_text
    from gaitshift.dds.own_messages import CMD_VEL_TOPIC, VelocityCommand_
    from gaitshift.dds.transport import open_participant, topic_writer

    writer = topic_writer(open_participant(domain, iface), CMD_VEL_TOPIC, VelocityCommand_)

    def put(msg: VelocityCommand_) -> None:
        writer.write(msg)
        reader = "" if writer.get_matched_subscriptions() else " (no brain reading yet)"
        typer.echo(command_text(msg) + reader)

    typer.echo(KEYS_HELP + " and quit", err=True)
    with KeyReader() as keys:
        key_loop(keys, KeySteer(), put, threading.Event())
