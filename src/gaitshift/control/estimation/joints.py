"""Joint position/velocity filter: a steady-state Kalman filter per joint, all joints at once.

Model of each joint (constant velocity driven by white acceleration of density ``s_a``)::

    x = [q, qd],   x_{k+1} = F x_k + w_k,   F = [[1, dt], [0, 1]],
    Q = s_a^2 [[dt^3/3, dt^2/2], [dt^2/2, dt]]                                   (Bar-Shalom 2001, 6.2.2)
    z_k = x_k + v_k,   Rz = diag(s_q^2, s_qd^2)     (encoder position, driver velocity)

The gain ``K`` of the stationary filter solves the discrete Riccati equation once (scipy
``solve_discrete_are``); each tick is then ``x <- (I - K) F x + K z``, two (2, 2) @ (2, nj) products.
The same gain serves every joint (same sensors); a joint's filtered velocity combines the encoder's
position differences (low noise, quantised) with the driver's velocity (noisy, no lag).
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import solve_discrete_are

from gaitshift.errors import InputError


class JointVelocityFilter:
    """Filtered joint positions and velocities from encoder and driver readings.

    Args:
        n_joints: number of joints.
        dt: tick period, s.
        pos_std: std of an encoder reading, rad.
        vel_std: std of a driver velocity reading, rad/s.
        accel_density: white joint acceleration density of the model, rad/s^2/sqrt(Hz).
    """

    def __init__(self, n_joints: int, dt: float, pos_std: float, vel_std: float, accel_density: float):
        for name, value in (("dt", dt), ("pos_std", pos_std), ("vel_std", vel_std), ("accel_density", accel_density)):
            if not value > 0:
                raise InputError(f"joint_filter.{name}", value, "a number > 0")
        f = np.array([[1.0, dt], [0.0, 1.0]])
        q = accel_density**2 * np.array([[dt**3 / 3.0, dt**2 / 2.0], [dt**2 / 2.0, dt]])
        rz = np.diag([pos_std**2, vel_std**2])
        p_prior = solve_discrete_are(f.T, np.eye(2), q, rz)  # predicted covariance, steady state
        self.gain = p_prior @ np.linalg.inv(p_prior + rz)  # (2, 2)
        self.a = (np.eye(2) - self.gain) @ f  # (2, 2): x <- a x + gain z
        self.state = np.zeros((2, n_joints))  # x = [q; qd], updated in place (the compiled tick shares it)
        self._z = np.zeros((2, n_joints))
        self._started = False

    def reset(self, q: np.ndarray, qd: np.ndarray | None = None) -> None:
        """Start from positions (nj,) and velocities (nj,) (zero if None)."""
        self.state[0] = q
        self.state[1] = 0.0 if qd is None else qd
        self._started = True

    def update(self, q: np.ndarray, qd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Feed one tick of readings (nj,); return the filtered (q, qd), fresh arrays (nj,)."""
        if not self._started:
            self.reset(q, qd)
        z = self._z
        z[0] = q
        z[1] = qd
        x = self.a.dot(self.state)
        x += self.gain.dot(z)
        self.state[...] = x
        return x[0], x[1]
