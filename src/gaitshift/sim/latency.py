"""Loop latency: the command computed from the readings of tick k acts on the plant at tick k + L.

``L`` ticks stand for the whole sensing-computation-actuation delay of a real loop (sensor transport,
estimator, QP, motor drivers). For a loop that runs once per tick only their sum matters, so it is
modelled as one first-in first-out pipe on the torques; before the first command has gone through,
the plant receives the first command computed (the standing torques).

Compensation (``predict=True``): the controller knows the ``L`` commands already sent and the joint
accelerations ``qdd_j`` its QP planned for them, so it acts on the state predicted at the tick its own
command will take effect (semi-implicit Euler, as MuJoCo integrates)::

    v_{j+1} = v_j + dt qdd_j,   q_{j+1} = q_j (+) dt v_{j+1}     for the L pending commands      (1)

(``(+)`` = ``mj_integratePos``: the quaternion of the free joint integrates on SO(3)).
"""

from __future__ import annotations

from collections import deque
from typing import Any

import mujoco
import numpy as np

from gaitshift.errors import InputError
from gaitshift.scenario.sim_settings import LATENCY_RANGE

MAX_LATENCY = LATENCY_RANGE[1]


class CommandPipe:
    """The torque FIFO of ``latency`` ticks and the state prediction (1) of the module docstring.

    Args:
        model: the controller's ``MjModel`` (for ``mj_integratePos``).
        latency: ticks, 0 .. :data:`MAX_LATENCY`.
        predict: compensate with (1).
    """

    def __init__(self, model: Any, latency: int, predict: bool = True) -> None:
        self.check(latency)
        self.model = model
        self.latency = int(latency)
        self.predict_on = bool(predict) and self.latency > 0
        self.dt = float(model.opt.timestep)
        self._tau: deque[np.ndarray] = deque()
        self._qdd: deque[np.ndarray] = deque()

    @staticmethod
    def check(latency: Any) -> None:
        """Raise :class:`InputError` unless ``latency`` is an integer number of ticks in range."""
        if isinstance(latency, bool) or not isinstance(latency, int | np.integer) or not 0 <= latency <= MAX_LATENCY:
            raise InputError("latency", latency, f"an integer number of ticks in [0, {MAX_LATENCY}]")

    def predict(self, qpos: np.ndarray, qvel: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The state (nq,), (nv,) at the tick the next command acts, from the state now, eq. (1)."""
        if not self.predict_on or not self._qdd:
            return qpos, qvel
        q, v = qpos.copy(), qvel.copy()
        for qdd in self._qdd:
            v += self.dt * qdd
            mujoco.mj_integratePos(self.model, q, v, self.dt)
        return q, v

    def send(self, tau: np.ndarray, qdd: np.ndarray | None) -> np.ndarray:
        """Queue the command ``tau`` (nu,) (its planned accelerations ``qdd`` (nv,), None if the QP
        failed: zero assumed) and return the torques that act on the plant now."""
        if self.latency == 0:
            return tau
        acc = np.zeros(self.model.nv) if qdd is None else np.asarray(qdd, float)
        if not self._tau:  # the pipe starts full of the first command
            self._tau.extend(tau.copy() for _ in range(self.latency))
            self._qdd.extend(np.zeros_like(acc) for _ in range(self.latency))
        self._tau.append(tau.copy())
        self._qdd.append(acc.copy())
        self._qdd.popleft()
        return self._tau.popleft()
