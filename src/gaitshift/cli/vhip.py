"""``gaitshift teleop``: drive the online VHIP running generator (paper 003) from the keyboard.

Arrow keys change the command by +/-0.3 m/s (up/down: forward, left/right: lateral), space stops,
q quits (stops to rest first). The live line shows the time, the step count, the command and the
planned CoM speed. On exit the whole run is written as a trajectory file.

Without a keyboard (tests, scripts) pass ``--script "up wait=2 up wait=2 down stop"`` or pipe the
same tokens on stdin (read when stdin is not a terminal). Tokens: up, down, left, right, stop,
quit, wait=<seconds>.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import typer

from gaitshift.cli.app import app, number, out_file
from gaitshift.cli.keys import KeyReader
from gaitshift.cli.web import web_port_option
from gaitshift.errors import InfeasibleError, InputError
from gaitshift.planners.vhip.generator import VhipGenerator
from gaitshift.scenario import load_scenario
from gaitshift.scenario.commands import KEYS, VHIP_STEP, key_change, parse_script
from gaitshift.trajectory.formats import SUFFIXES

#: longest run, s (a scenario's runs are at most 10 minutes too)
MAX_TIME = 600.0


def read_stdin_script() -> str:
    """The key script piped on stdin.

    Raises:
        InputError: stdin is not UTF-8 text.
    """
    try:
        return sys.stdin.read()
    except UnicodeDecodeError as exc:
        raise InputError("stdin", f"byte {exc.start} is not UTF-8", "UTF-8 text of key tokens") from None


def _status(gen: VhipGenerator) -> str:
    c, v = gen.command_velocity, gen.planned_velocity
    return (
        f"t={gen.t:7.3f} s  steps={gen.step_count:4d}  command=({c[0]:+.2f}, {c[1]:+.2f})  "
        f"planned=({v[0]:+.3f}, {v[1]:+.3f}) m/s  {gen.state}"
    )


def _apply(gen: VhipGenerator, action: str) -> bool:
    """Apply one key action; True when the user asked to quit."""
    if action in KEYS:
        dvx, dvy, _ = key_change(action, VHIP_STEP)  # paper 003 has no yaw-rate command
        c = gen.command_velocity
        if dvx or dvy:
            gen.command(c[0] + dvx, c[1] + dvy)
    elif action in ("stop", "quit"):
        gen.stop()
    return action == "quit"


def _finish(gen: VhipGenerator) -> None:
    """Request the stop and run until at rest (the ramp-down and State Switching 3 take a few s)."""
    gen.stop()
    limit = gen.t + 120.0
    while not gen.finished:
        if gen.t > limit:  # pragma: no cover - the stop always completes within a few steps
            raise InfeasibleError(f"the stop did not complete by t = {gen.t:.1f} s")
        gen.step()


def _run_script(gen: VhipGenerator, actions: list[tuple[str, float]], max_time: float) -> None:
    gen.tick()  # plan the start with the initial command
    for action, sec in actions:
        if action == "wait":
            n = min(round(sec / gen.dt), round((max_time - gen.t) / gen.dt))
            if n > 0 and not gen.finished:
                gen.advance(n)
        elif _apply(gen, action):
            break
        typer.echo(f"{action:>5s}  {_status(gen)}")
    _finish(gen)


def _run_keyboard(gen: VhipGenerator, max_time: float) -> None:  # pragma: no cover - needs a TTY
    typer.echo("arrows: speed +/-0.3 m/s (up/down forward, left/right lateral), space: stop, q: quit")
    t0 = time.monotonic()
    with KeyReader() as keys:
        while not gen.finished and gen.t < max_time:
            quit_ = any([_apply(gen, a) for a in keys.poll(0.02)])  # noqa: C419 - apply every key
            n = int((time.monotonic() - t0) / gen.dt) - round(gen.t / gen.dt)
            if n > 0:
                gen.advance(n)
            sys.stdout.write("\r" + _status(gen) + "   ")
            sys.stdout.flush()
            if quit_:
                break
    _finish(gen)


@app.command("teleop")
def teleop_cmd(
    scenario: str = typer.Argument(
        "paper003-variable-speed",
        help="A vhip scenario (name or YAML); its command profile is ignored, the keys give the commands.",
    ),
    out: Path = typer.Option(Path("teleop.npz"), "--out", help="Trajectory written on exit (.npz, .csv, .json)."),
    script: str | None = typer.Option(
        None, "--script", help="Key tokens instead of the keyboard: up down left right stop quit wait=<s>."
    ),
    max_time: float = typer.Option(MAX_TIME, "--max-time", help="Request the stop after this many seconds (<= 600)."),
    sim: bool = typer.Option(False, "--sim", help="Drive the simulated robot closed loop (locomotion generator)."),
    robot: str = typer.Option("g1", "--robot", help="With --sim: built-in robot name or robot YAML path."),
    viewer: bool | None = typer.Option(
        None,
        "--viewer/--no-viewer",
        help="With --sim: MuJoCo viewer (default: when a display exists; else a status line).",
    ),
    realtime: bool = typer.Option(True, "--realtime/--no-realtime", help="With --sim: pace to the wall clock."),
    web: bool = typer.Option(False, "--web", help="With --sim: a browser page with the view and speed controls."),
    web_port: int = web_port_option(),
) -> None:
    """Interactive running (paper 003): arrow keys change the speed command by 0.3 m/s (up/down forward,
    left/right lateral), space stops, q quits; shows the planned speed and step count; writes the run
    (stopped at rest) on exit. Without a terminal, key tokens come from --script or stdin."""
    out_file(out, "--out", SUFFIXES)
    number(max_time, "--max-time", 0.0, MAX_TIME, open_low=True)
    if web and not sim:
        raise InputError("--web", "without --sim", "--web together with --sim")
    source = "--script"
    if script is None and not sys.stdin.isatty() and not web:  # with --web the page gives the commands
        script, source = read_stdin_script(), "stdin"
    actions = parse_script(script, source) if script is not None else None
    if sim:
        from gaitshift.cli.live import teleop_sim

        teleop_sim(robot, actions, out, max_time, viewer, realtime, (web, web_port))
        return
    sc = load_scenario(scenario)
    if sc.planner != "vhip":
        raise InputError("scenario", scenario, "a vhip scenario (planner: vhip)")
    gen = VhipGenerator(sc)
    if actions is not None:
        _run_script(gen, actions, max_time)
    else:  # pragma: no cover - needs a TTY
        _run_keyboard(gen, max_time)
    traj = gen.trajectory()
    traj.save(out)
    n_ev = sum(1 for e in gen.events if e.kind.startswith("clamp"))
    typer.echo(f"{_status(gen)}\n{len(traj)} samples, {gen.step_count} steps, {n_ev} clamped commands; wrote {out}")
