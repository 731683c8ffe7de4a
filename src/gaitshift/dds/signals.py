"""SIGINT/SIGTERM caught for a process that must end cleanly (write its summary, leave the robot
damping): the signal's name is kept and the loop ends at its next tick."""

from __future__ import annotations

import signal
from typing import Any

__all__ = ["StopSignals"]


class StopSignals:
    """SIGINT/SIGTERM set :attr:`why` (the signal's name); the previous handlers come back on
    :meth:`restore`."""

    def __init__(self) -> None:
        self.why = ""
        self.previous = {s: signal.signal(s, self.handle) for s in (signal.SIGINT, signal.SIGTERM)}

    def handle(self, signum: int, _frame: Any) -> None:
        self.why = signal.Signals(signum).name

    def restore(self) -> None:
        for s, h in self.previous.items():
            signal.signal(s, h)
