"""The command-script format of ``gaitshift teleop``: key tokens that drive a streaming generator.

A script is whitespace-, comma- or semicolon-separated tokens (case-insensitive); one table,
:data:`KEYS`, says what each key token changes, and each driven generator has its step per axis:

* ``up`` / ``down``: forward speed command +/- one step; ``left`` / ``right``: lateral speed command
  +/- one step (left is +y);
* ``turn-left`` / ``turn-right``: yaw-rate command +/- one step;
* ``stop``: request the stop to rest; ``quit``: stop and end the script;
* ``wait=<seconds>`` (or ``wait:<seconds>``): let the generator run, 0 <= seconds <= :data:`MAX_WAIT`.

The same tokens come from ``--script`` or, when stdin is not a terminal, from stdin.
"""

from __future__ import annotations

import math
import re

from gaitshift.errors import InputError

#: token -> the change of the command (vx, vy, yaw rate) it makes, in steps of the driven generator
KEYS: dict[str, tuple[int, int, int]] = {
    "up": (1, 0, 0),
    "down": (-1, 0, 0),
    "left": (0, 1, 0),
    "right": (0, -1, 0),
    "turn-left": (0, 0, 1),
    "turn-right": (0, 0, -1),
}
#: steps (vx m/s, vy m/s, yaw rate rad/s) of one key press: paper 003's runner (speeds of m/s, no yaw
#: command) and the live locomotion generator of ``teleop --sim`` (a walking robot's finer steps)
VHIP_STEP = (0.3, 0.3, 0.0)
LOCOMOTION_STEP = (0.1, 0.05, 0.2)
#: tokens without an argument
ACTIONS = (*KEYS, "stop", "quit")


def key_change(action: str, step: tuple[float, float, float]) -> tuple[float, float, float]:
    """The change (vx, vy, yaw rate) that key token ``action`` (of :data:`KEYS`) makes with ``step``."""
    dvx, dvy, dw = KEYS[action]
    return dvx * step[0], dvy * step[1], dw * step[2]


#: longest single wait, s
MAX_WAIT = 3600.0
_WAIT = re.compile(r"wait[=:](.*)", re.IGNORECASE | re.DOTALL)
TOKENS_HELP = "tokens " + ", ".join(ACTIONS) + ", wait=<seconds>"


def parse_script(text: str, field: str = "--script") -> list[tuple[str, float]]:
    """Tokens of a key script -> [(action, seconds)]; action in :data:`ACTIONS` or ``'wait'``
    (seconds is 0 except for waits).

    Raises:
        InputError: an unknown token, or a wait that is not a number in [0, MAX_WAIT]; the message
            names ``field`` and the token.
    """
    out: list[tuple[str, float]] = []
    for tok in re.split(r"[\s,;]+", text.strip()):
        if not tok:
            continue
        low = tok.lower()
        m = _WAIT.fullmatch(tok)
        if m:
            out.append(("wait", _seconds(m.group(1), tok, field)))
        elif low in ACTIONS:
            out.append((low, 0.0))
        else:
            raise InputError(field, _clip(tok), TOKENS_HELP)
    return out


def _seconds(text: str, tok: str, field: str) -> float:
    allowed = f"wait=<seconds> with 0 <= seconds <= {MAX_WAIT:g}"
    try:
        sec = float(text)
    except ValueError:
        raise InputError(field, _clip(tok), allowed) from None
    if not (math.isfinite(sec) and 0 <= sec <= MAX_WAIT):
        raise InputError(field, _clip(tok), allowed)
    return sec


def _clip(tok: str, limit: int = 60) -> str:
    return tok if len(tok) <= limit else tok[: limit - 3] + "..."
