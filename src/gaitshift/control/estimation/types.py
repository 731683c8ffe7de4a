"""Value types of the state estimator: what the robot senses, and what the estimator returns.

Frames: ``world`` is z-up with gravity ``(0, 0, -g)``; the ``IMU`` frame is the frame of the IMU site
(MuJoCo's ``gyro``/``accelerometer`` sensors report in it); the ``base`` is the body that carries the
free joint (the G1's pelvis). All units SI; quaternions are ``(w, x, y, z)`` as in MuJoCo.

Every type is a frozen dataclass holding numpy arrays; the estimator never mutates an array it has
returned (each tick's arrays are fresh, or read-only). The per-tick path builds :class:`BaseState` and
:class:`EstimatedState` with :func:`new_base_state` and :func:`new_estimated_state`: the same frozen
objects, their slots filled through the slot descriptors instead of the dataclass ``__init__``'s
``object.__setattr__`` per field (2x cheaper: 1.1 against 2.3 µs for 7 fields).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from gaitshift.control.estimation.calibration import GyroCalibration
from gaitshift.control.estimation.lie import mat_of_quat

#: the four (left, right) flag pairs as shared read-only arrays (2,) bool, keyed by the pair: the
#: per-tick contact, stance and slip flags the estimator returns (no array built per tick)
FLAG_PAIRS = {(a, b): np.array([a, b]) for a in (False, True) for b in (False, True)}
for _flags in FLAG_PAIRS.values():
    _flags.flags.writeable = False


@dataclass(frozen=True, slots=True)
class ImuReading:
    """One IMU sample in the IMU frame, covering the tick's interval ``(t_k - dt, t_k]``.

    As a delta-angle / delta-velocity IMU reports it (a sampling IMU approximates both by its latest
    sample): ``gyro`` is the rate that rotates ``R(t_k - dt)`` into ``R(t_k)``, ``accel`` the mean
    specific force over the interval expressed in the IMU frame at ``t_k - dt``; the filters
    integrate ``R+ = R Exp(w dt)``, ``v+ = v + (R a + g) dt`` with R at the start of the interval.

    Attributes:
        gyro: (3,) angular velocity, rad/s.
        accel: (3,) specific force ``R^T (a - g)``, m/s^2 (reads ``+g`` up when at rest).
    """

    gyro: np.ndarray
    accel: np.ndarray


@dataclass(frozen=True, slots=True)
class JointReading:
    """Joint encoders and the velocity the motor drivers report, in the model's joint order.

    Attributes:
        q: (nj,) joint positions, rad.
        qd: (nj,) joint velocities, rad/s.
    """

    q: np.ndarray
    qd: np.ndarray


@dataclass(frozen=True, slots=True)
class FootForces:
    """Per-sole force signal (load cells or a torque-based estimate).

    Attributes:
        normal: (2,) [left, right] normal force, N (positive = pushing on the ground).
        cop: (2, 2) [left, right] centre of pressure (x along the sole, y across) in the sole frame, m,
            a NaN row where it is not known (a light load); None: not measured (the filter keeps each
            stance sole's centre).
    """

    normal: np.ndarray
    cop: np.ndarray | None = None


@dataclass(frozen=True, slots=True)
class FootKinematics:
    """The two soles seen from the IMU, from the joint encoders and the robot model.

    Attributes:
        pos: (2, 3) sole centre in the IMU frame, m.
        vel: (2, 3) its velocity relative to the IMU frame, expressed in the IMU frame, m/s
            (``J(q) qd``: the part of the sole velocity the joints produce).
        var: (2,) variance of each coordinate of ``pos`` from encoder noise, m^2: the isotropic
            covariance ``var I`` with the trace of ``J Sigma_q J^T`` (``var = s_q^2 |J|_F^2 / 3``).
        rot: (2, 3, 3) sole orientation in the IMU frame.
        rot_var: (2,) variance of each axis of ``rot`` from encoder noise, rad^2 (as ``var``, with
            the rotational Jacobian).
    """

    pos: np.ndarray
    vel: np.ndarray
    var: np.ndarray
    rot: np.ndarray
    rot_var: np.ndarray


@dataclass(frozen=True, slots=True)
class BaseState:
    """The IMU frame's state estimated by a base filter (world frame).

    Attributes:
        rot: (3, 3) orientation of the IMU frame in the world.
        pos: (3,) IMU position, m.
        vel: (3,) IMU linear velocity, m/s.
        omega: (3,) angular velocity in the IMU frame, bias-corrected, rad/s.
        gyro_bias, accel_bias: (3,) estimated IMU biases (zeros if the filter has none).
        cov_trace: trace of the covariance of the base error (rotation, velocity, position) in the
            filter's own error coordinates (rad^2 + (m/s)^2 + m^2); None for filters without one.
    """

    rot: np.ndarray
    pos: np.ndarray
    vel: np.ndarray
    omega: np.ndarray
    gyro_bias: np.ndarray
    accel_bias: np.ndarray
    cov_trace: float | None


class BaseFilter(Protocol):
    """What every floating-base filter provides (``InvariantEKF``, ``LegOdometry``)."""

    def reset(
        self, rot: np.ndarray, pos: np.ndarray, vel: np.ndarray | None = None, gyro_bias: GyroCalibration | None = None
    ) -> None:
        """Restart from a known IMU pose (3, 3)/(3,) and velocity (3,) (zero if None), biases at zero
        or the gyro bias at a standstill calibration ``gyro_bias``."""
        ...

    def step(self, imu: ImuReading, feet: FootKinematics, contact: np.ndarray, dt: float) -> BaseState:
        """Advance one tick of ``dt`` s: IMU propagation, then the stance-foot correction.

        ``contact``: (2,) bool, [left, right] feet in stance at this tick.
        """
        ...

    def advance(
        self, imu: ImuReading, feet: FootKinematics, contact: np.ndarray, dt: float
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, float | None]:
        """:meth:`step` without building the :class:`BaseState`: (rot (3, 3), [vel; pos] (2, 3), omega (3,),
        cov_trace); ``rot`` is the filter's own array, valid until the next tick (the estimator's path)."""
        ...

    def place_contacts(self, cop: np.ndarray) -> None:
        """The point of each stance sole to take as still from now on: ``cop`` (2, 2), sole-frame x, y, m
        (a NaN row keeps that sole's last point)."""
        ...


@dataclass(frozen=True, slots=True)
class EstimatedState:
    """What the controller sees at one tick: the estimated robot state (world frame, SI).

    Attributes:
        base_pos: (3,) base (free-joint body) origin, m.
        base_quat: (4,) base orientation (w, x, y, z).
        base_vel: (3,) base origin linear velocity, world frame, m/s.
        base_omega: (3,) base angular velocity, world frame, rad/s.
        q, qd: (nj,) filtered joint positions, rad, and velocities, rad/s.
        contact: (2,) bool, [left, right] sole in contact: force, sole height and speed, and the plan
            fused (:mod:`gaitshift.control.estimation.contact_fusion`).
        stance: (2,) bool, sole carrying a clear load: the force trigger alone (hysteresis), the flags
            the base filter uses.
        slip: (2,) bool, stance sole sliding: the slowest point of its support moves faster than the
            slip threshold (:mod:`gaitshift.control.estimation.slip`; a pivot is no slip).
        foot_vel: (2, 3) estimated world velocity of each sole centre, m/s.
        com: (3,) whole-body centre of mass, m.
        com_vel: (3,) its velocity, m/s.
        cov_trace: trace of the base-error covariance (see :class:`BaseState`); None if the filter
            has no covariance.
    """

    base_pos: np.ndarray
    base_quat: np.ndarray
    base_vel: np.ndarray
    base_omega: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    contact: np.ndarray
    stance: np.ndarray
    slip: np.ndarray
    foot_vel: np.ndarray
    com: np.ndarray
    com_vel: np.ndarray
    cov_trace: float | None

    def qpos(self) -> np.ndarray:
        """MuJoCo ``qpos`` (7 + nj,): base position, base quaternion, joint positions."""
        return np.concatenate([self.base_pos, self.base_quat, self.q])

    def qvel(self) -> np.ndarray:
        """MuJoCo ``qvel`` (6 + nj,): world linear velocity, body-frame angular velocity, joints."""
        rot = mat_of_quat(self.base_quat)
        return np.concatenate([self.base_vel, rot.T @ self.base_omega, self.qd])


_new = object.__new__


def _slot_setters(cls: type, names: tuple[str, ...]) -> tuple[Any, ...]:
    return tuple(cls.__dict__[name].__set__ for name in names)


_BASE = _slot_setters(BaseState, ("rot", "pos", "vel", "omega", "gyro_bias", "accel_bias", "cov_trace"))
_EST = _slot_setters(
    EstimatedState,
    (
        "base_pos",
        "base_quat",
        "base_vel",
        "base_omega",
        "q",
        "qd",
        "contact",
        "stance",
        "slip",
        "foot_vel",
        "com",
        "com_vel",
    ),
)
_EST_TRACE = EstimatedState.__dict__["cov_trace"].__set__


def new_base_state(
    rot: np.ndarray,
    pos: np.ndarray,
    vel: np.ndarray,
    omega: np.ndarray,
    gyro_bias: np.ndarray,
    accel_bias: np.ndarray,
    cov_trace: float | None,
) -> BaseState:
    """``BaseState(rot, pos, vel, omega, gyro_bias, accel_bias, cov_trace)``, built for the per-tick path."""
    out = _new(BaseState)
    s = _BASE
    s[0](out, rot), s[1](out, pos), s[2](out, vel), s[3](out, omega)
    s[4](out, gyro_bias), s[5](out, accel_bias), s[6](out, cov_trace)
    return out


def new_estimated_state(
    base_pos: np.ndarray,
    base_quat: np.ndarray,
    base_vel: np.ndarray,
    base_omega: np.ndarray,
    q: np.ndarray,
    qd: np.ndarray,
    contact: np.ndarray,
    stance: np.ndarray,
    slip: np.ndarray,
    foot_vel: np.ndarray,
    com: np.ndarray,
    com_vel: np.ndarray,
    cov_trace: float | None,
) -> EstimatedState:
    """``EstimatedState(...)`` (same argument order), built for the per-tick path."""
    out = _new(EstimatedState)
    s = _EST
    s[0](out, base_pos), s[1](out, base_quat), s[2](out, base_vel), s[3](out, base_omega), s[4](out, q)
    s[5](out, qd), s[6](out, contact), s[7](out, stance), s[8](out, slip), s[9](out, foot_vel), s[10](out, com)
    s[11](out, com_vel)
    _EST_TRACE(out, cov_trace)
    return out
