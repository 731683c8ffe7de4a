"""The command-script format of ``gaitshift teleop``: key tokens that drive the online VHIP generator.

A script is whitespace-, comma- or semicolon-separated tokens (case-insensitive):

* ``up`` / ``down``: forward speed command +/- :data:`KEY_STEP` m/s; ``left`` / ``right``: lateral
  speed command +/- :data:`KEY_STEP` m/s (left is +y);
* ``turn-left`` / ``turn-right``: yaw-rate command (``teleop --sim`` only, see
  :data:`gaitshift.sim.teleop.SIM_KEYS`);
* ``stop``: request the stop to rest; ``quit``: stop and end the script;
* ``wait=<seconds>`` (or ``wait:<seconds>``): let the generator run, 0 <= seconds <= :data:`MAX_WAIT`.

The same tokens come from ``--script`` or, when stdin is not a terminal, from stdin.
"""

from __future__ import annotations

import math
import re

from gaitshift.errors import InputError

#: command change per arrow key press, m/s
KEY_STEP = 0.3
#: token -> (d vx, d vy) of the speed command, m/s
KEYS: dict[str, tuple[float, float]] = {
    "up": (KEY_STEP, 0.0),
    "down": (-KEY_STEP, 0.0),
    "left": (0.0, KEY_STEP),
    "right": (0.0, -KEY_STEP),
}
#: tokens without an argument
ACTIONS = (*KEYS, "turn-left", "turn-right", "stop", "quit")
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
