"""Latency and age compensation: the state at the tick the command acts, predicted from the frame's.

A command computed from a frame acts ``n = L + a`` ticks after the frame's readings were taken: ``L`` the
loop's latency the controller is told (``ControllerSettings.latency``: the command's way to the motors, a
sensing delay), ``a`` the frame's age (ticks between its readings and the tick the controller acts at, for
a host that knows it: the DDS brain in lockstep counts it on the robot's clock, :mod:`gaitshift.dds.lockstep`;
a tick that brought no new readings acts on the last ones, a tick older). The controller acts on the state
predicted for that tick from the ``n`` commands sent last and the joint accelerations ``qdd_j`` its QP
planned for them (semi-implicit Euler, as MuJoCo integrates)::

    v_{j+1} = v_j + dt qdd_j,   q_{j+1} = q_j (+) dt v_{j+1}     for the n pending commands      (1)

The contact from the torques takes the estimated state before (1): the prediction carries the QP's own
accelerations, with which eq. (2) of :mod:`~gaitshift.control.estimation.torque_contact` gives back the
forces the QP assumed (4 ticks of latency: every g1-walk touch-down taken 13-95 ticks early).
"""

from __future__ import annotations

from collections import deque
from typing import Any

import mujoco
import numpy as np

__all__ = ["LatencyPredictor"]


class LatencyPredictor:
    """Eq. (1) of the module docstring over the last ``latency + age`` commands sent, ``age`` up to
    ``max_age`` ticks.

    Attributes:
        latency: ticks between a frame and its command acting, always (``L``).
        pending: the accelerations (nv,) of the last ``latency + max_age`` commands, oldest first.
    """

    def __init__(self, model: Any, latency: int, max_age: int) -> None:
        self.model = model
        self.dt = float(model.opt.timestep)
        self.latency = int(latency)
        self.pending: deque[np.ndarray] = deque(maxlen=max(self.latency + int(max_age), 1))

    def predict(self, qpos: np.ndarray, qvel: np.ndarray, age: int = 0) -> tuple[np.ndarray, np.ndarray]:
        """The state (nq,), (nv,) at the tick the next command acts, from the state (nq,), (nv,) of a frame
        ``age`` ticks old."""
        n = min(self.latency + int(age), len(self.pending))
        if n <= 0:
            return qpos, qvel
        q, v = qpos.copy(), qvel.copy()
        for j in range(len(self.pending) - n, len(self.pending)):
            v += self.dt * self.pending[j]
            mujoco.mj_integratePos(self.model, q, v, self.dt)
        return q, v

    def sent(self, qdd: np.ndarray | None) -> None:
        """The command just sent planned ``qdd`` (nv,) (None when the QP failed: zero assumed)."""
        acc = np.zeros(self.model.nv) if qdd is None else np.asarray(qdd, float)
        if not self.pending:  # the commands before the first: the first command, planned at rest
            self.pending.extend(np.zeros_like(acc) for _ in range(self.pending.maxlen or 1))
        self.pending.append(acc.copy())
