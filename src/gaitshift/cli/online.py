"""``gaitshift teleop``: drive the online VHIP running generator (paper 003) from the keyboard.

Arrow keys change the command by +/-0.3 m/s (up/down: forward, left/right: lateral), space stops,
q quits (stops to rest first). The live line shows the time, the step count, the command and the
planned CoM speed. On exit the whole run is written as a trajectory file.

Without a keyboard (tests, scripts) pass ``--script "up wait=2 up wait=2 down stop"`` or pipe the
same tokens on stdin (read when stdin is not a terminal). Tokens: up, down, left, right, stop,
quit, wait=<seconds>.
"""

from __future__ import annotations

import math
import os
import re
import select
import sys
import time
from pathlib import Path
from typing import Optional

import typer

from ..errors import InfeasibleError, InputError
from ..planners.online import OnlineGenerator
from ..scenario import load_scenario
from ..trajectory import check_suffix
from .app import app

#: command change per arrow key press, m/s
KEY_STEP = 0.3
KEYS = {"up": (KEY_STEP, 0.0), "down": (-KEY_STEP, 0.0), "left": (0.0, KEY_STEP), "right": (0.0, -KEY_STEP)}
_ESCAPES = {"\x1b[A": "up", "\x1b[B": "down", "\x1b[C": "right", "\x1b[D": "left",
            "w": "up", "s": "down", "a": "left", "d": "right", " ": "stop", "q": "quit", "\x03": "quit"}
_WAIT = re.compile(r"^wait[=:]([0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)$")


def parse_script(text: str) -> list[tuple[str, float]]:
    """Tokens of a key script -> [(action, seconds)]; action in KEYS, 'stop', 'quit' or 'wait'.

    Raises:
        InputError: an unknown token (names the token), a non-finite or negative wait.
    """
    out: list[tuple[str, float]] = []
    for tok in re.split(r"[\s,;]+", text.strip()):
        if not tok:
            continue
        low = tok.lower()
        m = _WAIT.match(low)
        if m:
            sec = float(m.group(1))
            if not math.isfinite(sec) or sec > 3600:
                raise InputError("--script", tok, "wait=<seconds> with 0 <= seconds <= 3600")
            out.append(("wait", sec))
        elif low in KEYS or low in ("stop", "quit"):
            out.append((low, 0.0))
        else:
            raise InputError("--script", tok, "tokens up, down, left, right, stop, quit, wait=<seconds>")
    return out


def _status(gen: OnlineGenerator) -> str:
    c, v = gen.command_velocity, gen.planned_velocity
    return (f"t={gen.t:7.3f} s  steps={gen.step_count:4d}  command=({c[0]:+.2f}, {c[1]:+.2f})  "
            f"planned=({v[0]:+.3f}, {v[1]:+.3f}) m/s  {gen.state}")


def _apply(gen: OnlineGenerator, action: str) -> bool:
    """Apply one key action; True when the user asked to quit."""
    if action in KEYS:
        dvx, dvy = KEYS[action]
        c = gen.command_velocity
        gen.command(c[0] + dvx, c[1] + dvy)
    elif action in ("stop", "quit"):
        gen.stop()
    return action == "quit"


def _finish(gen: OnlineGenerator) -> None:
    """Request the stop and run until at rest (the ramp-down and State Switching 3 take a few s)."""
    gen.stop()
    limit = gen.t + 120.0
    while not gen.finished:
        if gen.t > limit:  # pragma: no cover - the stop always completes within a few steps
            raise InfeasibleError(f"the stop did not complete by t = {gen.t:.1f} s")
        gen.step()


def _run_script(gen: OnlineGenerator, actions: list[tuple[str, float]], max_time: float) -> None:
    gen.tick()  # plan the start with the initial command
    for action, sec in actions:
        if action == "wait":
            n = min(int(round(sec / gen.dt)), int(round((max_time - gen.t) / gen.dt)))
            if n > 0 and not gen.finished:
                gen.advance(n)
        elif _apply(gen, action):
            break
        typer.echo(f"{action:>5s}  {_status(gen)}")
    _finish(gen)


def _run_keyboard(gen: OnlineGenerator, max_time: float) -> None:  # pragma: no cover - needs a TTY
    import termios
    import tty

    fd = sys.stdin.fileno()
    old = termios.tcgetattr(fd)
    tty.setcbreak(fd)
    typer.echo("arrows: speed +/-0.3 m/s (up/down forward, left/right lateral), space: stop, q: quit")
    t0 = time.monotonic()
    buf = ""
    try:
        while not gen.finished and gen.t < max_time:
            ready, _, _ = select.select([sys.stdin], [], [], 0.02)
            if ready:
                buf += os.read(fd, 16).decode(errors="ignore")
            quit_ = False
            while buf:
                key = next((k for k in _ESCAPES if buf.startswith(k)), None)
                if key is None:
                    if buf.startswith("\x1b") and len(buf) < 3:
                        break  # incomplete escape sequence
                    buf = buf[1:]
                    continue
                buf = buf[len(key):]
                quit_ |= _apply(gen, _ESCAPES[key])
            n = int((time.monotonic() - t0) / gen.dt) - int(round(gen.t / gen.dt))
            if n > 0:
                gen.advance(n)
            sys.stdout.write("\r" + _status(gen) + "   ")
            sys.stdout.flush()
            if quit_:
                break
    finally:
        termios.tcsetattr(fd, termios.TCSADRAIN, old)
        sys.stdout.write("\n")
    _finish(gen)


@app.command("teleop")
def teleop_cmd(
    scenario: str = typer.Argument("paper003-variable-speed", help="A vhip scenario (name or YAML); its "
                                   "command profile is ignored, the keys give the commands."),
    out: Path = typer.Option(Path("teleop.npz"), "--out", help="Trajectory written on exit (.npz, .csv, .json)."),
    script: Optional[str] = typer.Option(None, "--script", help="Key tokens instead of the keyboard: "
                                         "up down left right stop quit wait=<s>."),
    max_time: float = typer.Option(600.0, "--max-time", help="Request the stop after this many seconds."),
) -> None:
    """Interactive running (paper 003): arrow keys change the speed command by 0.3 m/s (up/down forward,
    left/right lateral), space stops, q quits; shows the planned speed and step count; writes the run
    (stopped at rest) on exit. Without a terminal, key tokens come from --script or stdin."""
    check_suffix(out, "--out")
    if not (math.isfinite(max_time) and max_time > 0):
        raise InputError("--max-time", max_time, "a finite number of seconds > 0")
    sc = load_scenario(scenario)
    if sc.planner != "vhip":
        raise InputError("scenario", scenario, "a vhip scenario (planner: vhip)")
    if script is None and not sys.stdin.isatty():
        script = sys.stdin.read()
    actions = parse_script(script) if script is not None else None
    gen = OnlineGenerator(sc)
    if actions is not None:
        _run_script(gen, actions, max_time)
    else:  # pragma: no cover - needs a TTY
        _run_keyboard(gen, max_time)
    traj = gen.trajectory()
    traj.save(out)
    n_ev = sum(1 for e in gen.events if e.kind.startswith("clamp"))
    typer.echo(f"{_status(gen)}\n{len(traj)} samples, {gen.step_count} steps, {n_ev} clamped commands; wrote {out}")
