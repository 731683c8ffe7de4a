"""Loop latency: the command computed from the frame of tick k acts on the plant at tick k + L.

``L`` ticks stand for the whole sensing-computation-actuation delay of a real loop (sensor transport,
estimator, QP, motor drivers). For a loop that runs once per tick only their sum matters, so it is
modelled as one first-in first-out pipe on the motor torques; before the first command has gone
through, the plant receives the first command computed (the standing torques). The controller, told
the same ``L``, compensates it by prediction (:mod:`gaitshift.control.state`, eq. (1)).
"""

from __future__ import annotations

from collections import deque
from typing import Any

import numpy as np

from gaitshift.errors import InputError
from gaitshift.scenario.sim_settings import LATENCY_RANGE

MAX_LATENCY = LATENCY_RANGE[1]


class CommandDelay:
    """The torque FIFO of ``latency`` ticks (module docstring).

    Args:
        latency: ticks, 0 .. :data:`MAX_LATENCY`.
    """

    def __init__(self, latency: int) -> None:
        self.check(latency)
        self.latency = int(latency)
        self._tau: deque[np.ndarray] = deque()

    @staticmethod
    def check(latency: Any) -> None:
        """Raise :class:`InputError` unless ``latency`` is an integer number of ticks in range."""
        if isinstance(latency, bool) or not isinstance(latency, int | np.integer) or not 0 <= latency <= MAX_LATENCY:
            raise InputError("latency", latency, f"an integer number of ticks in [0, {MAX_LATENCY}]")

    def send(self, tau: np.ndarray) -> np.ndarray:
        """Queue the torques ``tau`` (nu,) and return the torques that act on the plant now."""
        if self.latency == 0:
            return tau
        if not self._tau:  # the pipe starts full of the first command
            self._tau.extend(tau.copy() for _ in range(self.latency))
        self._tau.append(tau.copy())
        return self._tau.popleft()
