"""What crosses the truth barrier: a :class:`SensorFrame` in, a :class:`MotorCommand` out.

A world (the in-process simulation :mod:`gaitshift.sim`, the Unitree low-level protocol, a user's own
simulator) hands the controller (:class:`gaitshift.control.controller.Controller`) one frame per
control period and applies the command it returns. Both hold plain arrays only, one entry per motor
in the controller's ``motor_names`` order; the controller never sees a world's ``MjData``.

Each motor applies the Unitree low-level law

.. math::

    \\tau_{motor} = \\tau + k_p (q - q_{meas}) + k_d (\\dot q - \\dot q_{meas})            (1)

with ``q_meas``, ``dq_meas`` its own encoder readings; torque control is ``kp = kd = 0``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from gaitshift.errors import InputError

__all__ = ["MotorCommand", "OracleState", "SensorFrame"]


def _vector(field: str, value: Any, size: int | None, allowed: str) -> np.ndarray:
    """``value`` as a finite float array of shape (size,) (any length when ``size`` is None)."""
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(field, value, allowed) from None
    if a.ndim != 1 or (size is not None and a.size != size) or not np.all(np.isfinite(a)):
        raise InputError(field, _short(value), allowed)
    return a


def _points(value: Any) -> np.ndarray | None:
    """``value`` as an (M, 3) finite float array (M >= 0), or None."""
    if value is None:
        return None
    allowed = "an (M, 3) array of finite points, m (camera frame)"
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError("SensorFrame.depth_points", _short(value), allowed) from None
    if a.ndim != 2 or a.shape[1] != 3 or not np.all(np.isfinite(a)):
        raise InputError("SensorFrame.depth_points", f"shape {a.shape}", allowed)
    return a


def _short(value: Any) -> str:
    text = np.array2string(np.asarray(value, dtype=object).ravel()[:8], separator=", ") if value is not None else "None"
    return text if len(text) < 120 else text[:117] + "..."


@dataclass(frozen=True)
class OracleState:
    """The world's truth, for a controller run with ``state="oracle"`` (a simulator's privileged
    channel, or a motion-capture system's): never read by an estimating controller.

    Attributes:
        qpos: (7 + n,) MuJoCo configuration (base position m, quaternion w x y z, joint angles rad).
        qvel: (6 + n,) MuJoCo velocity (base linear m/s world, angular rad/s base frame, joints rad/s).
        contact: (2,) bool, soles (left, right) touching the ground.
        sole_velocity: (2, 2) m/s, horizontal world velocity of each sole's body (slip).
    """

    qpos: np.ndarray
    qvel: np.ndarray
    contact: np.ndarray
    sole_velocity: np.ndarray


@dataclass(frozen=True)
class SensorFrame:
    """What a robot reports at one control tick (module docstring).

    Attributes:
        t: time, s, since the controller's first tick.
        imu_quat: (4,) the IMU's attitude, w x y z (world from IMU).
        imu_gyro: (3,) rad/s, IMU frame. imu_acc: (3,) m/s^2 specific force, IMU frame.
        q: (n,) rad, dq: (n,) rad/s, tau_est: (n,) N m, per motor in ``motor_names`` order.
        foot_force: (2,) N normal force per sole (left, right), or None: the robot has no such sensor.
        depth_points: (M, 3) m, a depth camera's frame as points in the camera frame (the robot YAML's
            ``sensors.depth_camera``), or None: no new frame this tick (or no camera).
        oracle: the world's truth, or None (module :class:`OracleState`).
    """

    t: float
    imu_quat: np.ndarray
    imu_gyro: np.ndarray
    imu_acc: np.ndarray
    q: np.ndarray
    dq: np.ndarray
    tau_est: np.ndarray
    foot_force: np.ndarray | None = None
    depth_points: np.ndarray | None = None
    oracle: OracleState | None = None

    @classmethod
    def checked(cls, n_motors: int, **fields: Any) -> SensorFrame:
        """A frame from user values, each checked: finite, of its shape (``n_motors`` per motor);
        :class:`InputError` naming the field otherwise."""
        t = fields.get("t")
        if isinstance(t, bool) or not isinstance(t, int | float | np.floating) or not 0 <= t < math.inf:
            raise InputError("SensorFrame.t", t, "a finite time >= 0 s")
        out: dict[str, Any] = {"t": float(t)}
        for name, size in (("imu_quat", 4), ("imu_gyro", 3), ("imu_acc", 3)):
            out[name] = _vector(f"SensorFrame.{name}", fields.get(name), size, f"{size} finite numbers")
        if abs(float(np.linalg.norm(out["imu_quat"])) - 1.0) > 1e-3:
            raise InputError("SensorFrame.imu_quat", _short(out["imu_quat"]), "a unit quaternion w, x, y, z")
        for name in ("q", "dq", "tau_est"):
            out[name] = _vector(
                f"SensorFrame.{name}", fields.get(name), n_motors, f"{n_motors} finite numbers (one per motor)"
            )
        force = fields.get("foot_force")
        out["foot_force"] = None if force is None else _vector("SensorFrame.foot_force", force, 2, "2 finite forces, N")
        out["depth_points"] = _points(fields.get("depth_points"))
        unknown = set(fields) - {*out, "oracle"}
        if unknown:
            raise InputError(
                "SensorFrame",
                sorted(unknown)[0],
                "t, imu_quat, imu_gyro, imu_acc, q, dq, tau_est, foot_force, depth_points",
            )
        return cls(oracle=fields.get("oracle"), **out)


@dataclass(frozen=True)
class MotorCommand:
    """Per motor (``motor_names`` order), eq. (1) of the module docstring.

    Attributes:
        q: (n,) rad target position; dq: (n,) rad/s target velocity.
        kp: (n,) N m/rad; kd: (n,) N m s/rad; tau: (n,) N m feed-forward torque.
    """

    q: np.ndarray
    dq: np.ndarray
    kp: np.ndarray
    kd: np.ndarray
    tau: np.ndarray

    @classmethod
    def torque(cls, tau: np.ndarray) -> MotorCommand:
        """Pure torque control: ``kp = kd = 0``, targets zero."""
        zero = np.zeros_like(tau)
        return cls(q=zero, dq=zero, kp=zero, kd=zero, tau=tau)

    def torques(self, q_meas: np.ndarray, dq_meas: np.ndarray) -> np.ndarray:
        """The torques (n,) N m the motors apply at the measured ``q_meas``, ``dq_meas``: eq. (1)."""
        out: np.ndarray = self.tau + self.kp * (self.q - q_meas) + self.kd * (self.dq - dq_meas)
        return out
