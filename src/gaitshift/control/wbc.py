"""Whole-body inverse-dynamics QP, solved once per control tick (docs/simulation.md).

Model, from MuJoCo's own quantities at the current state (``M = mj_fullM``, ``h = qfrc_bias -
qfrc_passive``, Jacobians ``mj_jac``/``mj_jacDot``)::

    M qdd + h = S^T tau + sum_s J_s^T w_s                                    (1)

with ``w_s = [F_s; tau_s]`` the contact wrench of stance sole s about its centre (world frame) and
``J_s`` (6, nv) the Jacobian of the sole frame (linear velocity of the sole centre, then angular).
Unknowns ``x = [qdd (nv), w (6 per stance sole)]``; the torques are the affine function
``tau = S (M qdd + h - sum_s J_s^T w_s)`` of them, so torque limits are linear inequalities in x.
Eliminating tau this way is exact and keeps the QP at nv + 6 ns variables (35 + 12 for the G1 in
double support). Gains, references and diagnostics: :mod:`gaitshift.control.wbc_data`; QP pieces:
:mod:`gaitshift.control.qp_terms`; the contact wrench cone: :mod:`gaitshift.control.wrench_cone`; the
fixed structure and work buffers per stance set: :mod:`gaitshift.control.qp_layout`.

Hard constraints:
    * floating-base rows of (1) (6 equations);
    * non-sliding stance feet: ``J_s qdd + Jdot_s qd = -K_v v_s`` (6 per stance foot);
    * contact wrench cone per stance sole (Caron, Pham, Nakamura, ICRA 2015): w_s is a wrench that
      forces at the sole's contact points, each in the friction pyramid ``|f_x| + |f_y| <= mu f_z``
      inscribed in Coulomb's cone (sole axes), can exert; this holds the CoP inside the sole and
      bounds the yaw moment. The faces are those of the points' own cone (32 for the G1's trapezoid);
    * per-foot normal-force cap ``F_z <= F_max`` (the touchdown/lift-off force ramp);
    * torque limits ``|tau| <= tau_max``.

Weighted tasks (least squares, accelerations in m/s^2 or rad/s^2):
    * CoM: ``sum F / m = cdd_ref + K_p (c_ref - c) + K_d (cd_ref - cd) + g e_z``. Expressed on the
      contact wrenches, this is exact (Newton's law for the whole robot) and needs no CoM Jacobian
      derivative; in flight it is absent (the CoM is ballistic whatever we do);
    * centroidal angular momentum damping: ``sum_s (c_s - c) x F_s + tau_s = -K_L L`` (Euler's law
      about the CoM, L from ``mj_subtreeVel``);
    * swing-foot pose (position PD + feedforward acceleration, flat sole with the reference yaw);
    * torso and pelvis orientation (upright, reference yaw);
    * posture (joint PD toward the standing pose) and a small regularisation; on the wrenches it is
      the least sum of squared point forces that exerts them, ``w_s^T B_s Q B_s^T w_s``
      (:func:`gaitshift.control.wrench_cone.min_norm_metric`, ``B_s = diag(R_s, R_s)``).

The cost is block diagonal: every task acts either on qdd or on w. Each block is assembled with one
product of the stacked, weighted task rows (``H = sum_t w_t A_t^T A_t``) into the layout's buffers,
and the QP goes straight to daqp (docs/simulation.md, "Controller tick").
"""

from __future__ import annotations

import mujoco
import numpy as np

from gaitshift.control.qp_layout import QpLayout, StanceTerms
from gaitshift.control.qp_terms import INF, SKEW_BASIS, quat_yaw_error, rotation_error, solve_qp
from gaitshift.control.wbc_data import Gains, TickInfo, TickReference
from gaitshift.control.wrench_cone import SoleCone
from gaitshift.robots.model import RobotModel

__all__ = ["Gains", "TickInfo", "TickReference", "WholeBodyController", "rotation_error"]


class _Views:
    """Views into one ``MjData`` of what the controller reads, taken once (an attribute of ``MjData``
    builds a new array object at every access). That ``MjData`` is the controller's own, set from the
    estimated state (:mod:`gaitshift.control.state`), never the plant's."""

    def __init__(self, data: mujoco.MjData, torso: int, pelvis: int) -> None:
        self.data = data
        self.qpos, self.qvel = data.qpos, data.qvel
        self.com, self.com_vel, self.L = data.subtree_com[0], data.subtree_linvel[0], data.subtree_angmom[0]
        self.bias, self.passive = data.qfrc_bias, data.qfrc_passive
        self.xpos, self.xmat, self.xquat = data.xpos, data.xmat, data.xquat
        self.torso_quat, self.pelvis_quat = data.xquat[torso], data.xquat[pelvis]


class WholeBodyController:
    """Inverse-dynamics QP for a floating-base robot with two multi-point soles (see module docstring).

    Args:
        plant: the controller's robot model (:class:`~gaitshift.robots.model.RobotModel`).
        posture: reference joint positions (nq,) (only the hinge entries are used).
        gains: task weights and gains.
    """

    def __init__(self, plant: RobotModel, posture: np.ndarray, gains: Gains | None = None) -> None:
        self.plant = plant
        self.gains = gains or Gains()
        m = plant.model
        self.nv, self.nu = m.nv, m.nu
        self.M = np.zeros((m.nv, m.nv))
        self.q_posture = posture[7:].copy()
        names = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, m.dof_jntid[d]) for d in plant.actuated_dofs]
        arms = set(plant.robot.arm_joints)
        self.arm = np.array([n in arms for n in names])
        knees = [names.index(k) for k in plant.robot.knees]  # (left, right)
        self.knee_dofs = plant.actuated_dofs[knees]
        self.knee_qadr = m.jnt_qposadr[m.dof_jntid[self.knee_dofs]]
        self.knee_range = m.jnt_range[m.dof_jntid[self.knee_dofs]]
        self._knee = [
            (int(d), (float(r[0]), float(r[1]))) for d, r in zip(self.knee_dofs, self.knee_range, strict=True)
        ]
        self.mass = plant.mass
        self.gravity = -float(m.opt.gravity[2])
        self.last_solver = "daqp"
        self._cones: dict[float, tuple[SoleCone, SoleCone]] = {}
        self._stances: dict[tuple[bool, bool], StanceTerms] = {}
        self._cached_gains: Gains | None = None
        dofs = np.concatenate([np.arange(6), plant.actuated_dofs])  # the dynamics and torque rows
        self._dofs: slice | np.ndarray = slice(None) if np.array_equal(dofs, np.arange(m.nv)) else dofs
        act = plant.actuated_dofs
        self._act: slice | np.ndarray = slice(6, m.nv) if np.array_equal(act, np.arange(6, m.nv)) else act
        self._views: _Views | None = None
        # the four task frames (left sole, right sole, torso, pelvis): bodies, points on them (sole
        # centres, body origins), Jacobians (4, 6, nv) (linear then angular), v = J qd, Jdot qd (4, 6),
        # world points (4, 3), sole rotations (2, 3, 3)
        soles = plant.soles
        self._body_ids = [soles[0].body, soles[1].body, plant.torso_body, plant.pelvis_body]
        self._bodies = np.array(self._body_ids)
        self._offset = np.zeros((4, 1, 3))  # the points in the body frames, as rows
        self._offset[:2, 0] = [s.centre for s in soles]
        self._tmp = np.zeros((4, 3, 3))
        rot = np.array([s.rotation for s in soles])
        self._sole_rot = None if np.array_equal(rot, np.broadcast_to(np.eye(3), rot.shape)) else rot
        self._J, self._Jdot = np.zeros((4, 6, m.nv)), np.zeros((4, 6, m.nv))
        self._v, self._Jd = np.zeros((4, 6)), np.zeros((4, 6))
        self._P, self._R = np.zeros((4, 3)), np.zeros((2, 3, 3))
        J, Jdot, P = self._J, self._Jdot, self._P
        # the pelvis on a free joint: angular velocity R qd[3:6] (MuJoCo's free joint turns in its body
        # frame), so its angular Jacobian is [0, R, 0] and its Jdot qd is R [w]x w = 0; only its angular
        # rows are used (orientation task)
        self._free_base = bool(
            m.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE
            and m.jnt_bodyid[0] == plant.pelvis_body
            and m.jnt_dofadr[0] == 0
        )
        frames = 3 if self._free_base else 4
        self._jac_args = [
            (J[i, :3], J[i, 3:], Jdot[i, :3], Jdot[i, 3:], P[i], self._body_ids[i]) for i in range(frames)
        ]
        self._pelvis_rot = J[3, 3:, 3:6]
        self._J24, self._Jdot24 = J.reshape(24, m.nv), Jdot.reshape(24, m.nv)
        self._v24, self._Jd24 = self._v.reshape(24), self._Jd.reshape(24)
        # PD terms of the frame tasks (4, 6): errors, velocity references, feedforward accelerations
        self._err, self._vref, self._ff = np.zeros((4, 6)), np.zeros((4, 6)), np.zeros((4, 6))
        self._rot_err = [self._err[i, 3:] for i in range(4)]  # written as +e: their gains are -K_p
        self._sole_quat = [np.zeros(4), np.zeros(4)]
        for s, sole in enumerate(soles):
            mujoco.mju_mat2Quat(self._sole_quat[s], sole.rotation.ravel())
        self._sole_quat_list = [q.tolist() for q in self._sole_quat]
        self._xquat_soles = [int(sole.body) for sole in soles]
        self._t = np.zeros(6)  # minus the centroidal targets: -[m cdd_des; -K_L L]
        self._gain_arrays()

    def _gain_arrays(self) -> None:
        """Gain-dependent constants (per-dof posture terms, CoM gains, torque-row limits, frame-task
        gains and weights), recomputed when the gains object changes."""
        g = self.gains
        if self._cached_gains is g:
            return
        w_post = np.where(self.arm, g.w_arm_posture, g.w_posture)
        self._w_diag = np.concatenate([np.zeros(6), w_post]) + g.w_reg_qdd
        # posture on f: -w (K_p (q_ref - q) - K_d qd) = c_q q + c_v qd - c_q q_ref
        self._post_q, self._post_v = w_post * g.posture_kp, w_post * g.posture_kd
        self._post_0 = -self._post_q * self.q_posture
        self._com_kp, self._com_kd = self.mass * np.array(g.com_kp), self.mass * np.array(g.com_kd)
        self._neg_mass = -self.mass
        self._weight = np.array([0.0, 0.0, self.mass * self.gravity])
        self._row_lim = np.concatenate([np.zeros(6), self.plant.torque_limit * g.torque_margin])
        self._neg_row_lim = -self._row_lim
        self._neg_limit = -self.plant.torque_limit
        self._neg_kv = -g.stance_kv
        scale = self.mass * 0.1
        self._w_cent = np.array([g.w_com / self.mass**2] * 3 + [g.w_angmom / scale**2] * 3)
        sw, up = np.full(6, g.swing_kp), np.full(6, g.torso_kp)
        self._kp = np.array([sw, sw, up, up]) * [1.0, 1.0, 1.0, -1.0, -1.0, -1.0]  # position errors are -e
        self._kd = np.array([np.full(6, g.swing_kd)] * 2 + [np.full(6, g.torso_kd)] * 2)
        foot = [g.w_swing] * 3 + [g.w_swing_rot] * 3
        self._w_task = np.array([foot, foot, [0.0] * 3 + [g.w_torso] * 3, [0.0] * 3 + [g.w_pelvis] * 3])
        self._stances.clear()
        self._cached_gains = g

    def _view(self, data: mujoco.MjData) -> _Views:
        if self._views is None or self._views.data is not data:
            self._views = _Views(data, self.plant.torso_body, self.plant.pelvis_body)
        return self._views

    def _stance(self, ref: TickReference) -> StanceTerms:
        """The stance set of ``ref`` (rebuilt when the gains or the assumed friction change)."""
        self._gain_arrays()
        key = (bool(ref.stance[0]), bool(ref.stance[1]))
        st = self._stances.get(key)
        if st is None:
            mu = self.gains.mu
            cones = self._cones.get(mu)
            if cones is None:
                soles = self.plant.soles
                cones = self._cones[mu] = (SoleCone.of(soles[0].points, mu), SoleCone.of(soles[1].points, mu))
            lay = QpLayout.build(tuple(s for s in (0, 1) if key[s]), cones, self.nv, self.nu)
            st = self._stances[key] = StanceTerms(lay, key, self._w_task, self._w_cent, self.gains.w_reg_f)
        return st

    # ------------------------------------------------------------------ kinematics
    def _frames(self, data: mujoco.MjData, vw: _Views) -> None:
        """Points, sole rotations, Jacobians, velocities and ``Jdot qd`` of the two soles, the torso and
        the pelvis (one gather of the four bodies' poses, one pass of ``mj_jac``/``mj_jacDot``)."""
        m = self.plant.model
        Rb = vw.xmat[self._bodies].reshape(4, 3, 3)
        np.multiply(Rb, self._offset, out=self._tmp)
        np.add(vw.xpos[self._bodies], self._tmp.sum(axis=2), out=self._P)
        if self._sole_rot is None:
            self._R[:] = Rb[:2]
        else:
            np.matmul(Rb[:2], self._sole_rot, out=self._R)
        if self._free_base:
            self._pelvis_rot[:] = Rb[3]
        for jp, jr, dp, dr, point, body in self._jac_args:
            mujoco.mj_jac(m, data, jp, jr, point, body)
            mujoco.mj_jacDot(m, data, dp, dr, point, body)
        np.matmul(self._J24, vw.qvel, out=self._v24)
        np.matmul(self._Jdot24, vw.qvel, out=self._Jd24)

    def _level_frames(self, feet: slice) -> np.ndarray:
        """The contact frames G_s (k, 3, 3) of the stance soles ``feet``: z up (the friction cone's axis is
        the ground's normal, not the sole's: a sole rolling onto its toe or heel, or tilted by the
        estimate, must not tilt the cone), x the sole's heading ``atan2(R_s[1, 0], R_s[0, 0])``."""
        x = self._R[feet, :2, 0]
        n = np.hypot(x[:, 0], x[:, 1])
        c, s = x[:, 0] / n, x[:, 1] / n
        G = np.zeros((len(c), 3, 3))
        G[:, 0, 0], G[:, 0, 1], G[:, 1, 0], G[:, 1, 1], G[:, 2, 2] = c, -s, s, c, 1.0
        return G

    def task_frames(self, data: mujoco.MjData) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The four task frames (left sole, right sole, torso, pelvis) at the state of ``data`` (after
        ``mj_forward``), as the QP uses them: Jacobians (4, 6, nv) (linear then angular; the torso's
        and the pelvis's linear rows are not tasks), ``Jdot qd`` (4, 6), points (4, 3) (sole centres,
        body origins) and sole rotations (2, 3, 3); copies."""
        self._frames(data, self._view(data))
        return self._J.copy(), self._Jd.copy(), self._P.copy(), self._R.copy()

    # ------------------------------------------------------------------ tasks
    def _centroidal_tasks(self, vw: _Views, ref: TickReference, st: StanceTerms) -> None:
        """CoM (Newton) and angular-momentum damping (Euler about the CoM) on the contact wrenches,
        plus their regularisation: the (6 ns, 6 ns) wrench block of the cost, ``T_w^T W T_w``
        (:mod:`gaitshift.control.qp_layout`)."""
        lay, nv = st.lay, self.nv
        d = self._P[lay.feet] - vw.com
        lay.skew[:] = (d @ SKEW_BASIS).reshape(-1, 3, 3)
        lay.reg[:] = st.reg @ lay.B
        # the views are of the controller's own MjData (the estimated state, control/state.py), never the plant's
        t = self._t  # minus the targets of the first six rows: -[m cdd_des; -K_L L]
        t[:3] = (
            self._neg_mass * ref.com_acc
            + self._com_kp * (vw.com - ref.com_pos)
            + self._com_kd * (vw.com_vel - ref.com_vel)
            - self._weight
        )
        np.multiply(vw.L, self.gains.angmom_kd, out=t[3:])
        Tw = lay.Tw.T * st.w_wrench
        np.matmul(Tw, lay.Tw, out=lay.H[nv:, nv:])
        np.matmul(Tw[:, :6], t, out=lay.f[nv:])

    def _motion_targets(self, vw: _Views, ref: TickReference, st: StanceTerms) -> np.ndarray:
        """Swing-foot pose and torso and pelvis orientation: minus the PD targets of the four frames,
        ``-a = -K_p e - K_d (v_ref - J qd) + Jdot qd - a_ff`` (4, 6)."""
        err, vref, ff = self._err, self._vref, self._ff
        if st.swing:
            np.subtract(self._P[:2], ref.foot_pos, out=err[:2, :3])  # -e
            vref[:2, :3] = ref.foot_vel
            vref[:2, 5] = ref.yaw_rate
            ff[:2, :3] = ref.foot_acc
        for s in st.swing:  # sole on terrain
            w, x, y, z = self._sole_quaternion(vw, s)
            self._rot_err[s][:] = quat_yaw_error(float(ref.yaw[s]), float(ref.foot_pitch[s]), w, x, y, z)
        vref[2:, 5] = ref.torso_yaw_rate
        yaw = float(ref.torso_yaw)
        self._rot_err[2][:] = quat_yaw_error(yaw, 0.0, *vw.torso_quat.tolist())
        self._rot_err[3][:] = quat_yaw_error(yaw, 0.0, *vw.pelvis_quat.tolist())
        a: np.ndarray = self._kp * err + self._kd * (self._v - vref) + self._Jd - ff
        return a

    def _sole_quaternion(self, vw: _Views, s: int) -> tuple[float, float, float, float]:
        """Unit quaternion (w, x, y, z) of sole s: its body's, times the sole's rotation in the body."""
        a, b, c, d = vw.xquat[self._xquat_soles[s]].tolist()
        w, x, y, z = self._sole_quat_list[s]
        return (
            a * w - b * x - c * y - d * z,
            a * x + b * w + c * z - d * y,
            a * y - b * z + c * w + d * x,
            a * z + b * y - c * x + d * w,
        )

    def _motion_tasks(self, vw: _Views, ref: TickReference, st: StanceTerms) -> None:
        """The (nv, nv) qdd block of the cost: the stacked task rows, posture (joint PD toward the
        standing pose) and regularisation on the diagonal."""
        lay, nv = st.lay, self.nv
        a = self._motion_targets(vw, ref, st)
        Jr = self._J24[st.rows]
        Jw = Jr.T * st.w_rows
        np.matmul(Jw, Jr, out=lay.H[:nv, :nv])
        lay.H_diag += self._w_diag
        fq = lay.f[:nv]
        np.matmul(Jw, a.ravel()[st.rows], out=fq)
        fq[6:] += self._post_q * vw.qpos[7:] + self._post_v * vw.qvel[6:] + self._post_0

    # ------------------------------------------------------------------ constraints
    def _constraints(self, st: StanceTerms, h: np.ndarray, ref: TickReference) -> None:
        """Refill the changing rows of the layout: floating-base dynamics and torque limits (one block,
        ``[M, -J_feet^T]`` at the base and actuated dofs), non-sliding feet, wrench cones, force caps
        (:mod:`gaitshift.control.qp_layout`)."""
        lay, nv = st.lay, self.nv
        A = lay.A
        r = slice(0, lay.rows["torque"].stop)
        A[r, :nv] = self.M[self._dofs]
        h_rows = h[self._dofs]
        np.subtract(self._row_lim, h_rows, out=lay.up["dynamics+torque"])
        np.subtract(self._neg_row_lim, h_rows, out=lay.lo["dynamics+torque"])
        if not lay.stance:
            return
        Jf = self._J[lay.feet].reshape(-1, nv)
        np.negative(Jf.T[self._dofs], out=A[r, nv:])
        A[lay.rows["feet"], :nv] = Jf
        b = lay.up["feet"]
        np.multiply(self._v[lay.feet].ravel(), self._neg_kv, out=b)
        b -= self._Jd[lay.feet].ravel()
        lay.lo["feet"][:] = b
        lay.bu[lay.cap] = ref.fz_max[lay.feet]
        lay.cone[:] = st.faces @ lay.B

    def _knee_bounds(self, vw: _Views, st: StanceTerms) -> None:
        """Bounds on the knees' accelerations that keep them ``limit_margin`` inside their range over
        ``limit_horizon`` s: ``q + v T + a T^2 / 2`` within the range. Without them the trailing knee of
        a fast running swing is driven straight into its limit just after lift-off (docs/simulation.md,
        "Top speed"). A stance knee gets the straightening side only: at a straight knee the hip's
        height has no first-order dependence on the knee angle (the leg's Jacobian loses its axial
        row), so a QP that lets a loaded knee reach its stop can no longer lower the CoM with it; on
        g1-stairs-down the leading leg landed straight on a lower tread and stayed locked in its stop
        (docs/simulation.md, "What decides it")."""
        g = self.gains
        T = g.limit_horizon
        lo_x, up_x = st.lay.lo["x"], st.lay.up["x"]
        for s in (0, 1):
            dof, (q_lo, q_hi) = self._knee[s]
            drift = float(vw.qpos[self.knee_qadr[s]]) + float(vw.qvel[dof]) * T
            lo = 2.0 * (q_lo + g.limit_margin - drift) / T**2
            hi = 2.0 * (q_hi - g.limit_margin - drift) / T**2
            if s not in st.swing:  # the straight knee is the end of the range nearer 0
                lo, hi = (lo, INF) if abs(q_lo) <= abs(q_hi) else (-INF, hi)
            lo_x[dof], up_x[dof] = min(lo, hi), max(lo, hi)

    def _free_knees(self, st: StanceTerms) -> None:
        """No bounds on the knees' accelerations."""
        lo_x, up_x = st.lay.lo["x"], st.lay.up["x"]
        for dof, _ in self._knee:
            lo_x[dof], up_x[dof] = -INF, INF

    def _solve(self, lay: QpLayout) -> np.ndarray | None:
        """The QP solution x, or None (:func:`gaitshift.control.qp_terms.solve_qp`)."""
        x, self.last_solver = solve_qp(lay.H, lay.f, lay.A, lay.bu, lay.bl, lay.sense)
        return x  # type: ignore[no-any-return]

    # ------------------------------------------------------------------ the QP
    def compute(self, data: mujoco.MjData, ref: TickReference) -> tuple[np.ndarray, TickInfo]:
        """Torques (nu,) for the current state. ``data`` must hold the forward quantities
        (:func:`~gaitshift.robots.model.forward_terms`, ``mj_forward`` or ``mj_step1``) and ``mj_subtreeVel``."""
        p = self.plant
        nv = self.nv
        vw = self._view(data)
        mujoco.mj_fullM(p.model, data, self.M)
        h = vw.bias - vw.passive
        st = self._stance(ref)
        lay = st.lay
        self._frames(data, vw)
        if lay.stance:
            lay.B_blocks[:] = self._level_frames(lay.feet)[:, None].transpose(0, 1, 3, 2)  # B = diag(G_s^T, ...)
            self._centroidal_tasks(vw, ref, st)
        self._motion_tasks(vw, ref, st)
        self._constraints(st, h, ref)
        x = None
        if self.gains.limit_horizon > 0:  # with the knee-limit bounds, then without if infeasible
            self._knee_bounds(vw, st)
            x = self._solve(lay)
            self._free_knees(st)
        if x is None:
            x = self._solve(lay)
        info = TickInfo(ok=x is not None, solver=self.last_solver)
        if x is None:
            # infeasible: drop the stance and torque constraints' coupling, keep posture (safe fallback)
            lim = p.torque_limit * self.gains.torque_margin
            qj, vj = vw.qpos[7:], vw.qvel[6:]
            tau = np.clip(self.gains.posture_kp * 0.5 * (self.q_posture - qj) - 2.0 * vj + h[self._act], -lim, lim)
            return tau, info
        tau = lay.A_torque @ x  # M_a qdd - J_a^T w
        tau += h[self._act]
        w = x[nv:]
        info.forces[lay.feet] = w.reshape(-1, 6)[:, :3]
        info.qdd, info.contact_wrenches, info.stance = x[:nv], w, lay.stance
        info.contact_jacobian = self._J[lay.feet].reshape(-1, nv).copy()
        np.maximum(tau, self._neg_limit, out=tau)
        return np.minimum(tau, p.torque_limit, out=tau), info
