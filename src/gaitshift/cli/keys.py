"""Key presses from a terminal, as the command tokens of :mod:`gaitshift.scenario.commands`.

Arrows or ``wasd`` change the speed, ``z``/``x`` the yaw rate, space stops, ``q`` (or Ctrl-C) quits.
Used by ``gaitshift teleop`` and ``gaitshift teleop --sim``.
"""

from __future__ import annotations

import os
import select
import sys

__all__ = ["KEY_ACTIONS", "KeyReader"]

KEY_ACTIONS = {
    "\x1b[A": "up",
    "\x1b[B": "down",
    "\x1b[C": "right",
    "\x1b[D": "left",
    "w": "up",
    "s": "down",
    "a": "left",
    "d": "right",
    "z": "turn-left",
    "x": "turn-right",
    " ": "stop",
    "q": "quit",
    "\x03": "quit",
}


class KeyReader:  # pragma: no cover - needs a TTY
    """Key presses from a terminal in cbreak mode, as actions (:data:`KEY_ACTIONS`); a context manager
    that restores the terminal."""

    def __enter__(self) -> KeyReader:
        import termios
        import tty

        self.fd = sys.stdin.fileno()
        self.old = termios.tcgetattr(self.fd)
        tty.setcbreak(self.fd)
        self.buf = ""
        return self

    def __exit__(self, *exc: object) -> None:
        import termios

        termios.tcsetattr(self.fd, termios.TCSADRAIN, self.old)
        sys.stdout.write("\n")

    def poll(self, timeout: float = 0.0) -> list[str]:
        """The actions typed since the last call (waits up to ``timeout`` s for the first)."""
        ready, _, _ = select.select([sys.stdin], [], [], timeout)
        if ready:
            self.buf += os.read(self.fd, 16).decode(errors="ignore")
        out = []
        while self.buf:
            key = next((k for k in KEY_ACTIONS if self.buf.startswith(k)), None)
            if key is None:
                if self.buf.startswith("\x1b") and len(self.buf) < 3:
                    break  # incomplete escape sequence
                self.buf = self.buf[1:]
                continue
            self.buf = self.buf[len(key) :]
            out.append(KEY_ACTIONS[key])
        return out
