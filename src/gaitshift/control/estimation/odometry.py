"""Baseline: leg odometry (stance-foot kinematics) with a complementary attitude filter.

Attitude (Mahony et al., IEEE TAC 2008, eqs. 13 and 32, "explicit complementary filter"): with
``u = R^T e_z`` the predicted up direction in the IMU frame and ``a_hat = a~ / |a~|`` the measured one::

    e = a_hat x u,   w = w~ - b_hat + e / tau_att,   d/dt b_hat = -e / (tau_att tau_b),   R+ = R Exp(w dt)

Velocity: each stance foot is still, so the IMU velocity is ``v_i = -R (w x y_i + dy_i/dt)`` with
``y_i`` the sole in the IMU frame and ``dy_i/dt = J qd`` (Bloesch et al., RSS 2012, eq. 8); their mean
``v_kin`` is blended with the integrated accelerometer::

    v+ = v_imu + (dt / tau_v) (v_kin - v_imu),   v_imu = v + (R (a~) + g) dt      (in flight: v+ = v_imu)

Position: a foot that touches down is anchored at ``d_i = p + R y_i``; in stance ``p = mean_i (d_i -
R y_i)`` (drift only from one anchor to the next), in flight ``p+ = p + v dt``. No accelerometer bias,
no covariance: this is the simple baseline the invariant EKF is measured against.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from gaitshift.control.estimation.calibration import GyroCalibration
from gaitshift.control.estimation.lie import SKEW, quat_of_mat
from gaitshift.control.estimation.tuning import FilterTuning
from gaitshift.control.estimation.types import BaseState, FootKinematics, ImuReading, new_base_state


class LegOdometry:
    """Leg odometry with a complementary attitude filter (module docstring).

    Args:
        tuning: time constants ``attitude_tau``, ``bias_tau``, ``velocity_tau`` (``FilterTuning``).
        gravity: g, m/s^2.
    """

    def __init__(self, tuning: FilterTuning | None = None, gravity: float = 9.81):
        self.tuning = tuning if tuning is not None else FilterTuning()
        self.gravity = np.array([0.0, 0.0, -gravity])
        self._quat = np.array([1.0, 0.0, 0.0, 0.0])
        self._rot9 = np.eye(3).ravel()
        self.rot = self._rot9.reshape(3, 3)
        self._pos = np.zeros(3)
        self._vel = np.zeros(3)
        self._bias = np.zeros(3)
        self._anchor = np.zeros((2, 3))
        self._anchored = [False, False]
        self._w = np.zeros(3)
        self._zero = np.zeros(3)  # the accelerometer bias this filter reports (read-only)
        self._zero.flags.writeable = False
        self._weights = {(True, False): np.array([1.0, 0.0]), (False, True): np.array([0.0, 1.0])}
        self._weights[True, True] = np.array([0.5, 0.5])

    def reset(
        self, rot: np.ndarray, pos: np.ndarray, vel: np.ndarray | None = None, gyro_bias: GyroCalibration | None = None
    ) -> None:
        """Restart at orientation (3, 3), position (3,) and velocity (3,) (zero if None); the gyro
        bias restarts at zero, or at the mean of a standstill calibration ``gyro_bias``."""
        self._quat[:] = quat_of_mat(rot)
        mujoco.mju_quat2Mat(self._rot9, self._quat)
        self._pos[:] = pos
        self._vel[:] = 0.0 if vel is None else vel
        self._bias[:] = 0.0 if gyro_bias is None else gyro_bias.bias
        self._anchored = [False, False]

    def place_contacts(self, cop: np.ndarray) -> None:
        """Leg odometry keeps each stance sole at its centre: its velocity blend reads the centre's velocity
        ``J(q) qd``, the only one the kinematics give; ``cop`` is not used (the InEKF uses it)."""

    def step(self, imu: ImuReading, feet: FootKinematics, contact: np.ndarray, dt: float) -> BaseState:
        """One tick: attitude, then velocity and position from the stance feet (module docstring)."""
        rot, vp, omega, _ = self.advance(imu, feet, contact, dt)
        return new_base_state(rot.copy(), vp[1], vp[0], omega, self._bias.copy(), self._zero, None)

    def advance(
        self, imu: ImuReading, feet: FootKinematics, contact: np.ndarray, dt: float
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, float | None]:
        """:meth:`step` without the :class:`BaseState`: (rot (3, 3), [vel; pos] (2, 3), omega (3,), None);
        ``rot`` is the filter's own array, valid until the next tick (the estimator's path)."""
        t, rot = self.tuning, self.rot
        omega = imu.gyro - self._bias
        # attitude: e = a_hat x u with u = R^T e_z (third row of R)
        ax, ay, az = imu.accel.tolist()
        norm = math.sqrt(ax * ax + ay * ay + az * az)
        ux, uy, uz = rot[2].tolist()
        w = self._w
        if norm > 1e-6:
            ax, ay, az = ax / norm, ay / norm, az / norm
            e = (ay * uz - az * uy, az * ux - ax * uz, ax * uy - ay * ux)  # a_hat x u
            w[:] = e
            self._bias -= w * (dt / (t.attitude_tau * t.bias_tau))
            w *= 1.0 / t.attitude_tau
            w += omega
        else:
            w[:] = omega
        v_imu = self._vel + dt * (rot @ imu.accel + self.gravity)
        mujoco.mju_quatIntegrate(self._quat, w, dt)
        mujoco.mju_quat2Mat(self._rot9, self._quat)  # rot (a view) is now the end-of-tick orientation
        stance = [bool(contact[0]), bool(contact[1])]
        if stance[0] or stance[1]:
            weight = self._weights[stance[0], stance[1]]  # mean over the stance feet
            rel = feet.vel - feet.pos.dot(omega.dot(SKEW).reshape(3, 3))  # dy/dt + omega x y, both feet
            v_kin = -rot.dot(weight.dot(rel))
            self._vel = v_imu + (dt / t.velocity_tau) * (v_kin - v_imu)
            for i in (0, 1):
                if stance[i] and not self._anchored[i]:
                    self._anchor[i] = self._pos + rot.dot(feet.pos[i])
            self._pos = weight.dot(self._anchor - feet.pos.dot(rot.T))
        else:
            self._vel = v_imu
            self._pos = self._pos + dt * v_imu
        self._anchored = stance
        return self.rot, np.array((self._vel, self._pos)), omega, None
