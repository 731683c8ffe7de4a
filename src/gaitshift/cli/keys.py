"""Key presses from a terminal, as the command tokens of :mod:`gaitshift.scenario.commands`.

Arrows or ``wasd`` change the speed, ``z``/``x`` the yaw rate, space stops, ``q`` (or Ctrl-C) quits.
Used by ``gaitshift teleop``, ``gaitshift teleop --sim``, ``gaitshift dds cmd --teleop`` and
``gaitshift dds control --teleop`` (:func:`key_loop`, in a thread beside the brain's tick).
"""

from __future__ import annotations

import os
import select
import sys
import threading
from collections.abc import Callable
from typing import Any, TextIO

__all__ = ["KEY_ACTIONS", "KeyReader", "key_loop", "require_terminal"]

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


def require_terminal(flag: str) -> None:
    """:class:`~gaitshift.errors.InputError` naming ``flag`` when stdin is not a terminal to read keys from."""
    from gaitshift.errors import InputError

    if not sys.stdin.isatty():
        raise InputError(flag, "stdin", "a terminal to read the keys from")


class KeyReader:
    """Key presses from a terminal in cbreak mode, as actions (:data:`KEY_ACTIONS`); a context manager
    that restores the terminal.

    Args:
        fd: the terminal's file descriptor (None: stdin's). out: where the newline written when the
            terminal is restored goes (None: stdout).
    """

    def __init__(self, fd: int | None = None, out: TextIO | None = None) -> None:
        self.fd = sys.stdin.fileno() if fd is None else fd
        self.out = out

    def __enter__(self) -> KeyReader:
        import termios
        import tty

        self.old = termios.tcgetattr(self.fd)
        tty.setcbreak(self.fd)
        self.buf = ""
        return self

    def __exit__(self, *exc: object) -> None:
        import termios

        termios.tcsetattr(self.fd, termios.TCSADRAIN, self.old)
        (self.out or sys.stdout).write("\n")

    def poll(self, timeout: float = 0.0) -> list[str]:
        """The actions typed since the last call (waits up to ``timeout`` s for the first)."""
        ready, _, _ = select.select([self.fd], [], [], timeout)
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


def key_loop(keys: KeyReader, steer: Any, put: Callable[[Any], None], done: threading.Event) -> None:
    """Key presses to commands until ``done`` is set or the stop command (q) went: each action of ``keys``
    through ``steer.press`` (:class:`gaitshift.dds.cmdvel.KeySteer`: None for no command), the command to
    ``put``. Polls every 0.1 s, so ``done`` is seen within that time."""
    while not done.is_set():
        for action in keys.poll(0.1):
            msg = steer.press(action)
            if msg is None:
                continue
            put(msg)
            if msg.stop:
                return
