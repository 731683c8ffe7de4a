"""Leg kinematics seen from the IMU: soles, CoM and base in the IMU frame, from joint angles only.

The estimator owns a PRIVATE ``MjData`` of the robot model with the free joint at identity, so the
MuJoCo world frame of that data is the base frame ``B``. Per tick, for joint angles ``q`` and velocities
``qd``: ``mj_kinematics`` and ``mj_comPos`` give each point ``x_B`` (sole sites, whole-body CoM
``subtree_com``) and ``mj_jacSite``/``mj_jacSubtreeCom`` its Jacobian ``J_B`` (joint columns).
With the IMU site at ``(p_S, R_S)`` in ``B`` and ``w_S = R_S^T J_rot,S qd`` its angular velocity::

    y = R_S^T (x_B - p_S)                                           (position in the IMU frame)
    dy/dt = R_S^T (J_B - J_S) qd + y x w_S                          (velocity relative to the IMU)

(for an IMU on the base, ``J_S = 0`` and ``w_S = 0``). The sole-position noise from encoder noise
``s_q`` is ``J Sigma_q J^T``; the filters get its isotropic equivalent ``s_q^2 |J|_F^2 / 3`` per foot
(and the same with the rotational Jacobian for the sole orientation ``R_S^T R_sole``), refreshed every
``VAR_EVERY`` ticks (the rotational Jacobians are computed on those ticks only).
The simulator's ``MjData`` is never touched.

Per-tick cost (the estimator's hot path, docs/estimation.md "Measured cost"): for an IMU on the base
with the base's axes the result is the object's own buffers, filled in place (no per-tick objects);
the soles' orientations are a view of the private data's ``site_xmat`` (no copy); the positions are
subtracted row by row (contiguous 3-vectors: a strided operand is numpy's slow path); the CoM Jacobian
is that of subtree 0 (the world's) when the robot carries all the mass: the same numbers, and MuJoCo
computes it in half the time of the root's subtree.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np

from gaitshift.control.estimation.types import FootKinematics
from gaitshift.errors import InputError

VAR_EVERY = 8  # ticks between refreshes of the encoder-noise variance of the soles (J changes slowly)
#: what the kinematics read of a model: a model without geoms must agree on all of it
KINEMATIC_FIELDS = (
    "body_parentid",
    "body_pos",
    "body_quat",
    "body_ipos",
    "body_iquat",
    "body_mass",
    "body_inertia",
    "body_subtreemass",
    "jnt_type",
    "jnt_qposadr",
    "jnt_dofadr",
    "jnt_bodyid",
    "jnt_pos",
    "jnt_axis",
    "dof_bodyid",
    "site_bodyid",
    "site_pos",
    "site_quat",
    "qpos0",
)


@functools.lru_cache(maxsize=8)
def kinematic_model(robot: Any) -> Any:
    """The robot's model (:class:`gaitshift.robots.RobotConfig`) without geoms and meshes, for the
    estimator's private kinematics: ``mj_kinematics`` then poses bodies and sites only (a third less
    work on the G1's 71 geoms). Falls back to ``robot.model()`` when removing the geoms changes any of
    :data:`KINEMATIC_FIELDS` (e.g. masses inferred from the geoms), or when it does not compile without
    them (bodies whose only mass is their geoms')."""
    model = robot.model()
    spec = mujoco.MjSpec.from_file(str(robot.mjcf))
    robot.add_sites(spec)
    for item in [*spec.geoms, *spec.meshes]:
        spec.delete(item)
    try:
        bare = spec.compile()
    except ValueError:  # the bodies' masses came from their geoms (a model without inertial elements)
        return model
    same = all(np.array_equal(getattr(model, f), getattr(bare, f)) for f in KINEMATIC_FIELDS)
    return bare if same and bare.nsite == model.nsite else model


@dataclass(frozen=True, slots=True)
class BodyKinematics:
    """Everything the joints tell about the robot, in the IMU frame (one tick).

    Attributes:
        feet: the two soles (:class:`FootKinematics`; its arrays are views of ``points``).
        points: (4, 3) [left sole, right sole, whole-body CoM, base origin], m.
        points_vel: (4, 3) their velocities relative to the IMU frame, m/s.
        base_rot: (3, 3) base orientation in the IMU frame.
        base_omega: (3,) base angular velocity relative to the IMU frame, rad/s.
    """

    feet: FootKinematics
    points: np.ndarray
    points_vel: np.ndarray
    base_rot: np.ndarray
    base_omega: np.ndarray


class LegKinematics:
    """Sole and CoM kinematics of a floating-base MuJoCo model, in the IMU frame (module docstring).

    Args:
        model: ``mujoco.MjModel`` with one free joint (first) and hinge/slide joints.
        imu_site: name of the IMU site.
        sole_sites: (left, right) names of the sole-centre sites.
        encoder_std: std of one joint-position reading, rad.
    """

    def __init__(self, model: Any, imu_site: str, sole_sites: tuple[str, str], encoder_std: float = 0.0):
        free = [j for j in range(model.njnt) if int(model.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_FREE)]
        if len(free) != 1 or model.jnt_qposadr[free[0]] != 0:
            raise InputError("model", "MjModel", "a floating-base model (one free joint, first in qpos)")
        if model.nq != model.nv + 1:
            raise InputError("model", "MjModel", "hinge or slide joints besides the free joint")
        self.model = model
        self.data = mujoco.MjData(model)  # private: never the simulator's data
        self.n_joints = model.nv - 6
        self.encoder_std = float(encoder_std)
        self._imu = self._site(imu_site, "imu_site")
        self._soles = tuple(self._site(s, "sole_sites") for s in sole_sites)
        self._root = int(model.jnt_bodyid[free[0]])
        self.mass = float(model.body_subtreemass[self._root])
        self.imu_on_base = int(model.site_bodyid[self._imu]) == self._root
        self.jac = np.zeros((12, model.nv))  # sole L, sole R, CoM, base origin (zero) Jacobians
        self._jac_imu = np.zeros((3, model.nv))
        self._jac_imu_rot = np.zeros((3, model.nv))
        self._pts = np.zeros((4, 3))  # row 3: the base origin, fixed at 0 in the base frame
        self.sole_ids = self._sole_ids = np.array(self._soles)  # (2,) site ids of the soles
        self._pts_soles = self._pts[0:2]
        self._jac_rows = tuple(self.jac[3 * i : 3 * i + 3] for i in range(3))
        self.qvel = np.zeros(model.nv)  # joint velocities in [6:], free joint zero
        self._jacr = np.zeros((6, model.nv))  # rotational Jacobians of the soles
        self._jac_rate = np.zeros((3, model.nv))  # one rotational Jacobian for sole_rate
        self._jacr_rows = (self._jacr[0:3], self._jacr[3:6])
        self._rot_var = np.zeros(2)
        self._site_xpos = self.data.site_xpos  # views into the private MjData (fixed buffers)
        # the whole-body CoM: subtree 0 (the world's) when the robot carries all the mass (MuJoCo's
        # mj_jacSubtreeCom is twice as fast there), else the root's
        self._com_body = 0 if model.body_subtreemass[0] == model.body_subtreemass[self._root] else self._root
        self.com_view = self.data.subtree_com[self._com_body]  # (3,) the whole-body CoM in the base frame
        self._vel_flat = np.zeros(12)  # the points' velocities (4, 3), and the soles' orientations (2, 3, 3)
        self.vel = self._vel_flat.reshape(4, 3)
        #: the points in the IMU frame (rows 0:4, columns 0:3: ``points`` of the result) and rows 4:8 for
        #: their velocities, with a 1 in column 4 (positions) or 3 (velocities): ``points_aug @ [R^T; v; p]``
        #: is the world positions and velocities of the points (the estimator fills rows 4:8)
        self.points_aug = np.zeros((8, 5))
        self.points_aug[0:4, 4] = self.points_aug[4:8, 3] = 1.0
        self._y = self.points_aug[0:4, 0:3]
        # per-row subtractions of contiguous 3-vectors (a strided or broadcast operand is numpy's slow path)
        self._y_rows = (self._y[0], self._y[1], self._y[2])
        self._x_rows = (self.data.site_xpos[self._soles[0]], self.data.site_xpos[self._soles[1]])
        left, right = self._soles  # the soles' orientations (2, 3, 3): a view of their rows of site_xmat
        step, lo = abs(right - left), min(left, right)
        xmat = self.data.site_xmat
        rows = xmat[lo : lo + step + 1 : step] if step else np.lib.stride_tricks.as_strided(xmat[lo], (2, 9), (0, 8))
        self._rot = (rows if left <= right else rows[::-1]).reshape(2, 3, 3)
        self._ticks = 0
        self._var = np.zeros(2)
        self.data.qpos[:] = model.qpos0
        self.data.qpos[:7] = (0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0)
        self._qpos = self.data.qpos
        mujoco.mj_kinematics(model, self.data)
        self._set_base_constants()
        self._refresh_variances()

    def _site(self, name: str, field: str) -> int:
        sid = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_SITE, name)
        if sid < 0:
            names = [self.model.site(i).name for i in range(self.model.nsite)]
            raise InputError(field, name, "a site of the model: " + ", ".join(names))
        return int(sid)

    @classmethod
    def from_robot(cls, robot: Any, imu_site: str | None = None, encoder_std: float = 0.0) -> LegKinematics:
        """Kinematics of a :class:`gaitshift.robots.RobotConfig` (its sole sites), IMU at ``imu_site``
        (None: the robot's own, ``robot.imu_site``)."""
        return cls(kinematic_model(robot), imu_site or robot.imu_site, robot.SOLE_SITES, encoder_std)

    def compute(self, q: np.ndarray, qd: np.ndarray) -> BodyKinematics:
        """Kinematics at joint angles ``q`` (nj,) rad and velocities ``qd`` (nj,) rad/s.

        For an IMU on the base with the base's axes (the G1's pelvis IMU) the result's arrays are the
        object's own buffers, rewritten by the next call: read them before computing again."""
        self._qpos[7:] = q
        self.qvel[6:] = qd
        self.run_mujoco()
        if self.imu_axes_are_base:  # y = x_B - p_S straight from MuJoCo's arrays (row 3, -p_S, is fixed)
            y_rows, p_s = self._y_rows, self.p_s
            np.subtract(self._x_rows[0], p_s, y_rows[0])
            np.subtract(self._x_rows[1], p_s, y_rows[1])
            np.subtract(self.com_view, p_s, y_rows[2])
        else:
            self._site_xpos.take(self._sole_ids, axis=0, out=self._pts_soles)
            self._pts[2] = self.com_view
        pts, vel = self._pts, self.vel
        np.dot(self.jac, self.qvel, out=self._vel_flat)  # free-joint columns meet zeros
        if self.imu_axes_are_base:
            return self._body
        rot = np.matmul(self.data.site_xmat[self._imu].reshape(3, 3).T, self._rot)
        if not self.imu_on_base:
            y, ydot, base_rot, base_omega = self._relative_to_moving_imu(pts, vel, qd)
        else:
            y, ydot, base_rot, base_omega = (
                (pts - self.p_s).dot(self._rot_s),
                vel.dot(self._rot_s),
                self._base_rot,
                self._zero,
            )
        self._y[...] = y  # points_aug holds the points for every IMU
        feet = FootKinematics(pos=y[0:2], vel=ydot[0:2], var=self._var, rot=rot, rot_var=self._rot_var)
        return BodyKinematics(feet, y, ydot, base_rot, base_omega)

    def sole_jacobians(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """At joint angles ``q`` (nj,) rad: the soles' translational Jacobians on the joints (2, 3, nj) and
        the soles' positions from the IMU (2, 3) m, base frame. Leaves the tick count (the variance
        refresh's schedule) as it was; the next :meth:`compute` overwrites the rest."""
        ticks = self._ticks
        self.compute(q, np.zeros(self.n_joints))
        self._ticks = ticks
        return self.jac[0:6, 6:].reshape(2, 3, -1).copy(), self.points_aug[0:2, 0:3].copy()

    def run_mujoco(self) -> BodyKinematics:
        """The MuJoCo part of :meth:`compute` on the joint angles and velocities already in ``data.qpos[7:]``
        and ``qvel[6:]`` (the compiled tick writes them): poses, CoM, the Jacobians ``jac`` (12, nv) (the
        rotational ones on the variance-refresh ticks), the tick count and the variance refresh. For an
        IMU on the base with the base's axes, the returned object's arrays are filled by the caller
        (:func:`gaitshift.control.estimation.kernels.imu_frame_points`, or :meth:`compute`)."""
        m, d, rows = self.model, self.data, self._jac_rows
        mujoco.mj_kinematics(m, d)
        mujoco.mj_comPos(m, d)
        refresh = self._ticks % VAR_EVERY == 0  # the rotational Jacobians serve the variances only
        jacr = self._jacr_rows if refresh else (None, None)
        mujoco.mj_jacSite(m, d, rows[0], jacr[0], self._soles[0])
        mujoco.mj_jacSite(m, d, rows[1], jacr[1], self._soles[1])
        mujoco.mj_jacSubtreeCom(m, d, rows[2], self._com_body)
        self._ticks += 1
        if refresh:
            self._refresh_variances()
        return self._body

    def sole_rate(self, i: int, qd: np.ndarray) -> np.ndarray:
        """Angular velocity (3,) rad/s of sole ``i`` relative to the IMU, in the IMU frame, at the pose of
        the last :meth:`compute` and joint velocities ``qd`` (nj,): ``R_S^T (J_rot,i - J_rot,S) qd``."""
        m, d, jr = self.model, self.data, self._jac_rate
        mujoco.mj_jacSite(m, d, None, jr, self._soles[i])
        w_rel = jr[:, 6:].dot(qd)
        if not self.imu_on_base:
            mujoco.mj_jacSite(m, d, None, jr, self._imu)
            w_rel -= jr[:, 6:].dot(qd)
        out: np.ndarray = w_rel.dot(d.site_xmat[self._imu].reshape(3, 3))
        return out

    def _refresh_variances(self) -> None:
        """Encoder-noise variances of the soles' positions and orientations (module docstring); for an
        IMU on the base with the base's axes, the result object that holds the new arrays."""
        scale = self.encoder_std**2 / 3.0
        self._var = scale * np.square(self.jac[0:6, 6:]).reshape(2, -1).sum(axis=1)
        self._rot_var = scale * np.square(self._jacr[:, 6:]).reshape(2, -1).sum(axis=1)
        y = self._y
        feet = FootKinematics(pos=y[0:2], vel=self.vel[0:2], var=self._var, rot=self._rot, rot_var=self._rot_var)
        self._body = BodyKinematics(feet, y, self.vel, self._base_rot, self._zero)

    def _set_base_constants(self) -> None:
        """IMU site pose in the base frame (constant for an IMU on the base)."""
        d = self.data
        self._rot_s = d.site_xmat[self._imu].reshape(3, 3).copy()
        self.p_s = d.site_xpos[self._imu].copy()  # (3,) IMU site position in the base frame, m
        self._base_rot = self._rot_s.T.copy()
        #: the IMU sits on the base with the base's axes (then base_rot = I and the IMU omega is the base's)
        self.imu_axes_are_base = self.imu_on_base and bool(np.allclose(self._rot_s, np.eye(3), atol=1e-12))
        self._zero = np.zeros(3)
        np.subtract(self._pts, self.p_s, out=self._y)  # row 3 (the base origin): -p_S

    def _relative_to_moving_imu(
        self, pts: np.ndarray, vel: np.ndarray, qd: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Points and velocities in an IMU frame that moves with the joints (e.g. a torso IMU)."""
        m, d = self.model, self.data
        mujoco.mj_jacSite(m, d, self._jac_imu, self._jac_imu_rot, self._imu)
        rot_s = d.site_xmat[self._imu].reshape(3, 3).copy()
        p_s = d.site_xpos[self._imu].copy()
        w_s = rot_s.T @ (self._jac_imu_rot[:, 6:] @ qd)  # IMU angular velocity, IMU frame
        y = (pts - p_s) @ rot_s
        ydot = (vel - self._jac_imu[:, 6:] @ qd) @ rot_s + np.cross(y, w_s)
        return y, ydot, rot_s.T.copy(), -w_s
