"""The state estimator the controller talks to: sensors in, one :class:`EstimatedState` out per tick.

Per tick (period ``dt``)::

    stance   = ContactDetector(forces)                    hysteresis + debounce on the sole forces, released
                                                          where the last tick's fusion ruled a load out (veto)
    q, qd    = JointVelocityFilter(encoders, driver qd)   steady-state Kalman filter per joint
    kin      = LegKinematics(q, qd)                       soles, CoM, base in the IMU frame (private MjData)
    R, p, v  = filter.step(imu, kin.feet, stance, dt)     "inekf" (default) or "leg-odometry"
    x_w      = p + R y,   v_w = v + R (w x y + dy/dt)     every point y of kin (soles, CoM, base origin)
    w_i      = R (w_imu + R_S^T (J_rot,i - J_rot,S) qd)    sole angular velocity, world (low-passed)
    slip_i   = SlipDetector(stance, v_w,i, w_i, R R_i)      the slowest point of the support slides
    a_v      = e_z . R a_imu                              the IMU's specific force along the world vertical
    contact  = ContactFusion(forces, z_low, vz, planned, a_v)  force, sole height, plan and flight fused
                                                          (contact_fusion.py)

The slip test (:mod:`gaitshift.control.estimation.slip`) low-passes the sole's twist (time constant
``slip_tau``, reset in swing) and flags a stance sole when the slowest point of its support polygon
(its contact points, from the robot) moves faster than ``slip_speed`` horizontally: a pivot about the
toe keeps a support point still, a slide moves every point. A sole whose centre moves (slides or
pivots: the same low-pass, ``|LP(v_c)|_xy > slip_speed``) is no contact for the filter at the next tick:
the filter takes the sole centre as a still point, so its kinematics would drag the base estimate.

Two contact flags. ``stance`` (the force trigger alone) is what the base filter and the slip test
use: a sole the filter pins must carry a clear force (a lightly loaded sole can slide). ``contact`` is
the estimate of "the sole touches the floor": force, the sole's lowest point ``z_low`` and vertical
speed ``vz`` from this tick's estimate, and the plan's contact flags ``planned`` when the caller gives
them, fused (:mod:`gaitshift.control.estimation.contact_fusion`). In the loop the foot scheduler's
touch-down events read ``stance`` or :attr:`StateEstimator.landing` (the soles the fusion holds on by a
landing alone; :mod:`gaitshift.control.state`).

The CoM comes from MuJoCo (``subtree_com``/``mj_jacSubtreeCom``) on the estimator's own ``MjData``,
placed in the world with the estimated IMU pose; the simulator's data is never read.

Cost (docs/estimation.md "Measured cost"): the world positions and velocities of the four points come
from one product ``[y, 0, 1; dy/dt + w x y, 1, 0] @ [R^T; v; p]`` (LegKinematics.points_aug), the
filter's mean step without a :class:`BaseState` (``advance``), the forces, heights and speeds reach the
contact detector, the fused contact and the slip test as plain floats read once. The returned
``slip``, ``stance`` and ``contact`` flags are shared read-only arrays, every other returned array is fresh.
For an InEKF and an IMU with the base's axes (the G1) the tick runs on two compiled kernels around the
MuJoCo calls instead (:mod:`gaitshift.control.estimation.tick`; ``compiled=False``: the Python path
above, which the tests compare it with).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np

from gaitshift.control.estimation.calibration import GyroCalibration
from gaitshift.control.estimation.contact import ON_SIGMAS, ContactDetector
from gaitshift.control.estimation.contact_fusion import ContactFusion
from gaitshift.control.estimation.filters import DEFAULT_FILTER, make_filter
from gaitshift.control.estimation.inekf import InvariantEKF
from gaitshift.control.estimation.joints import JointVelocityFilter
from gaitshift.control.estimation.kinematics import LegKinematics, kinematic_model
from gaitshift.control.estimation.lie import SKEW, mat_of_quat
from gaitshift.control.estimation.noise import NoiseProfile
from gaitshift.control.estimation.slip import (
    NOISE_SIGMAS,
    SlipDetector,
    lowpass_factor,
    lowpass_rate_variance,
    still_speed_sigma,
)
from gaitshift.control.estimation.tuning import FilterTuning
from gaitshift.control.estimation.types import (
    FLAG_PAIRS,
    EstimatedState,
    FootForces,
    ImuReading,
    JointReading,
    new_estimated_state,
)
from gaitshift.errors import InputError

if TYPE_CHECKING:
    from gaitshift.control.estimation.tick import CompiledTick

SOLE_SITES = ("gaitshift_left_sole", "gaitshift_right_sole")


class StateEstimator:
    """Contact detection, joint filtering, base filter, CoM and slip, for one robot (module docstring).

    Args:
        model: ``mujoco.MjModel`` of the robot (one free joint, first); only read.
        dt: tick period, s.
        imu_site: name of the IMU site (its gyro/accelerometer frame).
        sole_sites: (left, right) sole-centre site names.
        filter: base filter name (:data:`gaitshift.control.estimation.filters.FILTERS`).
        noise: noise profile the sensors follow (name or :class:`NoiseProfile`); sets the tuning.
        tuning: explicit tuning (overrides ``noise``).
        contact_on, contact_off: contact thresholds, fractions of the robot weight.
        debounce: contact debounce, ticks.
        contact_window: samples of the moving average of the sole forces before the trigger.
        slip_speed: horizontal speed of the slowest support point above which a stance sole slips, m/s.
        slip_tau: time constant of the low-pass on the sole twist before that test, s.
        gravity: g, m/s^2.
        sole_points: per sole, its contact points (n, 3) in the sole-site frame, relative to the site, m
            (:attr:`gaitshift.robots.soles.SoleGeometry.points`): the lowest of them gives the sole's
            height for the fused contact, their convex hull its support for the slip test; None: the
            sole centre alone.
        compiled: run the tick on the compiled kernels (:mod:`gaitshift.control.estimation.tick`) when
            they cover the set-up (an InEKF, an IMU with the base's axes); False: the Python path.
    """

    def __init__(
        self,
        model: Any,
        dt: float,
        *,
        imu_site: str,
        sole_sites: tuple[str, str] = SOLE_SITES,
        filter: str = DEFAULT_FILTER,
        noise: str | NoiseProfile = "typical",
        tuning: FilterTuning | None = None,
        contact_on: float = 0.15,
        contact_off: float = 0.05,
        debounce: int = 2,
        contact_window: int = 1,
        slip_speed: float = 0.2,
        slip_tau: float = 0.03,
        gravity: float = 9.81,
        sole_points: tuple[np.ndarray, np.ndarray] | None = None,
        compiled: bool = True,
    ):
        if not dt > 0:
            raise InputError("estimator.dt", dt, "a period > 0 s")
        if not slip_speed > 0:
            raise InputError("estimator.slip_speed", slip_speed, "a speed > 0 m/s")
        if not slip_tau > 0:
            raise InputError("estimator.slip_tau", slip_tau, "a time constant > 0 s")
        self.dt = float(dt)
        self.tuning = tuning if tuning is not None else FilterTuning.from_profile(noise, dt)
        t = self.tuning
        self.kinematics = LegKinematics(model, imu_site, sole_sites, t.encoder_std)
        self.contact = ContactDetector(
            self.kinematics.mass * gravity, contact_on, contact_off, debounce, contact_window
        )
        c = self.contact
        force_std = max(c.on_force / ON_SIGMAS, 1e-9) * math.sqrt(c.window)  # one sample (noise_thresholds)
        self.fusion = ContactFusion(c.on_force, c.off_force, force_std, c.window, gravity=gravity)
        pts = sole_points if sole_points is not None else (np.zeros((1, 3)), np.zeros((1, 3)))
        left, right = (np.asarray(p, float).reshape(-1, 3) for p in pts)
        self._sole_point_list = [[tuple(p) for p in pts.tolist()] for pts in (left, right)]  # plain floats
        n = self.kinematics.n_joints
        self.joints = JointVelocityFilter(n, dt, t.encoder_std, t.joint_vel_std, t.joint_accel_density)
        self.filter_name = filter
        self.filter = make_filter(filter, t, gravity)
        self._axes_are_base = self.kinematics.imu_axes_are_base
        alpha = lowpass_factor(dt, slip_tau)
        #: the slip threshold's noise floor, m/s (slip.py eq. (4) times NOISE_SIGMAS)
        self.slip_floor = NOISE_SIGMAS * self._speed_noise(alpha)
        self.slip = SlipDetector(dt, max(slip_speed, self.slip_floor), slip_tau, sole_points)
        self._tick_rot, self._tick_feet_rot = np.eye(3), np.zeros((2, 3, 3))  # this tick's R and sole rotations
        self._points_aug = self.kinematics.points_aug  # (8, 5): [y, 0, 1; dy/dt + w x y, 1, 0]
        self._rel = self._points_aug[4:8, 0:3]
        self._affine = np.zeros((5, 3))
        self._omega_skew9 = np.zeros(9)
        self._omega_skew = self._omega_skew9.reshape(3, 3)
        self._compiled: CompiledTick | None = None  # the compiled tick, when it covers this set-up
        if compiled and isinstance(self.filter, InvariantEKF) and self._axes_are_base:
            from gaitshift.control.estimation.tick import CompiledTick  # numba: imported when used (0.3 s)

            parts = (self.kinematics, self.joints, self.filter, self.contact, self.fusion, self.slip)
            self._compiled = CompiledTick(*parts, (left, right), self.dt)

    def _speed_noise(self, alpha: float) -> float:
        """``sigma`` (m/s) of slip.py eq. (4) for this tuning, at the model's reference pose."""
        kin, t = self.kinematics, self.tuning
        jac, lever = kin.sole_jacobians(kin.model.qpos0[7:])
        reading_cov = np.diag([t.encoder_std**2, t.joint_vel_std**2])
        rate_var = lowpass_rate_variance(self.joints.a, self.joints.gain, reading_cov, alpha)
        return still_speed_sigma(jac, lever, rate_var, t.gyro_density**2 / self.dt, alpha)

    @property
    def landing(self) -> np.ndarray:
        """(2,) bool: the soles the last tick's fused contact holds on by a landing alone (a sole back at the
        ground level after it left the floor, its force not yet confirming it; contact_fusion.py)."""
        if self._compiled is not None:
            return self._compiled.landing()
        return np.array(self.fusion.landing, bool)

    @property
    def compiled(self) -> bool:
        """Whether :meth:`step` runs on the compiled kernels (:mod:`gaitshift.control.estimation.tick`)."""
        return self._compiled is not None

    @classmethod
    def from_robot(cls, robot: Any, dt: float, **kwargs: Any) -> StateEstimator:
        """Estimator for a :class:`gaitshift.robots.RobotConfig` (its model without geoms,
        :func:`~gaitshift.control.estimation.kinematics.kinematic_model`, its sole sites and points,
        its IMU site unless ``imu_site`` is given)."""
        left, right = (np.asarray(s.points) for s in robot.soles)
        kwargs.setdefault("imu_site", robot.imu_site)
        return cls(kinematic_model(robot), dt, sole_sites=robot.SOLE_SITES, sole_points=(left, right), **kwargs)

    def reset(
        self,
        qpos: np.ndarray,
        qvel: np.ndarray | None = None,
        contact: tuple[bool, bool] = (True, True),
        gyro_bias: GyroCalibration | None = None,
    ) -> None:
        """Restart from a known state: MuJoCo ``qpos`` (7 + nj,), ``qvel`` (6 + nj,) (zero if None),
        the stance flags (2,) and, if given, a standstill gyro-bias calibration (the filter's gyro-bias
        prior)."""
        qpos = np.asarray(qpos, dtype=float)
        qvel = np.zeros(qpos.size - 1) if qvel is None else np.asarray(qvel, dtype=float)
        if qpos.shape != (self.kinematics.n_joints + 7,) or qvel.shape != (self.kinematics.n_joints + 6,):
            raise InputError("estimator.reset", (qpos.shape, qvel.shape), "qpos (7 + nj,) and qvel (6 + nj,)")
        q, qd = qpos[7:], qvel[6:]
        kin = self.kinematics.compute(q, qd)
        rot_b = mat_of_quat(qpos[3:7] / np.linalg.norm(qpos[3:7]))
        rot = rot_b @ kin.base_rot.T  # IMU orientation
        pos = qpos[0:3] - rot @ kin.points[3]
        omega_w = rot_b @ qvel[3:6]
        vel = qvel[0:3] + np.cross(omega_w, pos - qpos[0:3])
        self.filter.reset(rot, pos, vel, gyro_bias)
        self.joints.reset(q, qd)
        self.contact.reset(contact)
        self.fusion.reset(contact)
        self.slip.reset()
        if self._compiled is not None:
            self._compiled.reset(contact)

    def _sole_twist(self, i: int, rates: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """World angular velocity (3,) rad/s and rotation (3, 3) of sole ``i`` at this tick, for the rate
        vector ``rates`` = (IMU rate (3,), joint velocities (nj,)): ``R (w_imu + R_S^T (J_rot,i -
        J_rot,S) qd)`` (:meth:`LegKinematics.sole_rate`; the slip test's ``twist``)."""
        rot = self._tick_rot
        return rot.dot(rates[:3] + self.kinematics.sole_rate(i, rates[3:])), rot.dot(self._tick_feet_rot[i])

    def step(
        self, imu: ImuReading, joints: JointReading, forces: FootForces, planned: np.ndarray | None = None
    ) -> EstimatedState:
        """One tick: readings in, the estimated state out (module docstring); ``planned`` (2,) bool: the
        contact flags of the controller's plan at this tick (None: the contact flags ignore the plan);
        ``forces.cop``, when given, places the filter's stance points (:meth:`BaseFilter.place_contacts`)."""
        if forces.cop is not None:
            self.filter.place_contacts(forces.cop)
        if self._compiled is not None:
            return self._compiled.step(imu, joints, forces, planned)
        normal = forces.normal.tolist()
        left, right = self.contact.update_values(normal)
        veto = self.fusion.veto  # of the last tick: the kinematics ruled a load out (contact_fusion.py)
        if veto[0] or veto[1]:
            self.contact.release(veto)
            left, right = left and not veto[0], right and not veto[1]
        q, qd = self.joints.update(joints.q, joints.qd)
        kin = self.kinematics.compute(q, qd)
        moving = self.slip.moving  # soles whose centre moved (slide or pivot) drop out of the filter
        stance = FLAG_PAIRS[left and not moving[0], right and not moving[1]]
        rot, vp, omega, cov_trace = self.filter.advance(imu, kin.feet, stance, self.dt)
        y = kin.points
        np.dot(omega, SKEW, self._omega_skew9)
        np.subtract(kin.points_vel, y.dot(self._omega_skew), self._rel)  # dy/dt + w x y
        affine = self._affine  # [R^T; v; p]
        affine[0:3] = rot.T
        affine[3:5] = vp
        xv_w = self._points_aug.dot(affine)  # rows 0:4: R y + p, rows 4:8: R (dy/dt + w x y) + v
        rows = xv_w.tolist()
        self._tick_rot, self._tick_feet_rot = rot, kin.feet.rot
        rates = np.concatenate((omega, qd))
        slip = FLAG_PAIRS[self.slip.update((left, right), rows[4:6], rates, self._sole_twist)]
        heights = self._lowest(rot[2].dot(kin.feet.rot).tolist(), rows)
        speeds = [math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) for v in rows[4:6]]
        a_v = float(rot[2].dot(imu.accel))  # the specific force along the world vertical (the flight rule)
        fused = self.fusion.update_values(normal, heights, [rows[4][2], rows[5][2]], planned, speeds, a_v)
        quat = np.empty(4)
        if self._axes_are_base:
            mujoco.mju_mat2Quat(quat, rot.reshape(9))
            omega_w = rot.dot(omega)
        else:
            mujoco.mju_mat2Quat(quat, rot.dot(kin.base_rot).reshape(9))
            omega_w = rot.dot(omega + kin.base_omega)
        return new_estimated_state(
            xv_w[3],
            quat,
            xv_w[7],
            omega_w,
            q,
            qd,
            fused,
            FLAG_PAIRS[left, right],
            slip,
            xv_w[4:6],
            xv_w[2],
            xv_w[6],
            cov_trace,
        )

    def _lowest(self, up: list[list[float]], x_w: list[list[float]]) -> list[float]:
        """World height (2,) of each sole's lowest contact point: ``z_s + min_j (R_s^T R^T e_z) . p_j``
        (``up`` (2, 3) = ``R_s^T R^T e_z``, the world vertical in each sole frame; ``x_w`` the world
        positions, soles first), in plain floats: a handful of points per sole."""
        out = []
        for i in (0, 1):
            ux, uy, uz = up[i]
            out.append(min([px * ux + py * uy + pz * uz for px, py, pz in self._sole_point_list[i]]) + x_w[i][2])
        return out
