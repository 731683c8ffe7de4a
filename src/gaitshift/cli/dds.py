"""Unitree low-level protocol commands: ``gaitshift dds robot ROBOT`` (the MuJoCo world behind the protocol)."""

from __future__ import annotations

import json
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
