"""Whole-body inverse-dynamics QP, solved once per control tick (docs/simulation.md).

Model, from MuJoCo's own quantities at the current state (``M = mj_fullM``, ``h = qfrc_bias -
qfrc_passive``, Jacobians ``mj_jac``/``mj_jacDot``)::

    M qdd + h = S^T tau + sum_i Jp_i^T f_i                                  (1)

with ``f_i`` the force at contact point i (the lowest points of the contact geoms of each stance
foot, world frame: the four sphere bottoms of the G1, the corners of a box sole). Unknowns
``x = [qdd (nv), f (3k)]``; the torques are the affine function
``tau = S (M qdd + h - Jc^T f)`` of them, so torque limits are linear inequalities in x. Eliminating
tau this way is exact and keeps the QP at nv + 3k variables (35 + 24 for the G1 in double support).
Gains, references and diagnostics: :mod:`gaitshift.control.wbc_data`; QP pieces:
:mod:`gaitshift.control.qp_terms`; the fixed structure per stance set (two-sided torque rows, the
constant friction and cap rows, reused each tick): :mod:`gaitshift.control.qp_layout`.

The cost is block diagonal: every task acts either on qdd or on f. Each block is assembled with one
product of the stacked, weighted task rows (``H = sum_t w_t A_t^T A_t``), and the QP goes straight to
daqp (docs/simulation.md, "Controller tick").

Hard constraints:
    * floating-base rows of (1) (6 equations);
    * non-sliding stance feet: ``J_foot qdd + Jdot_foot qd = -K_v v_foot`` (6 per stance foot);
    * friction pyramids ``|f_x|, |f_y| <= mu f_z`` and unilateral ``f_z >= 0`` per point; the CoP of a
      foot is then inside the convex hull of its points, i.e. inside the sole;
    * per-foot normal-force cap ``sum f_z <= F_max`` (the touchdown/lift-off force ramp);
    * torque limits ``|tau| <= tau_max``.

Weighted tasks (least squares, accelerations in m/s^2 or rad/s^2):
    * CoM: ``sum f / m = cdd_ref + K_p (c_ref - c) + K_d (cd_ref - cd) + g e_z``. Expressed on the
      contact forces, this is exact (Newton's law for the whole robot) and needs no CoM Jacobian
      derivative; in flight it is absent (the CoM is ballistic whatever we do);
    * centroidal angular momentum damping: ``sum (p_i - c) x f_i = -K_L L`` (Euler's law about the
      CoM, L from ``mj_subtreeVel``);
    * swing-foot pose (position PD + feedforward acceleration, flat sole with the reference yaw);
    * torso and pelvis orientation (upright, reference yaw);
    * posture (joint PD toward the standing pose) and a small regularisation.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from gaitshift.control.plant_view import PlantView
from gaitshift.control.qp_layout import QpLayout
from gaitshift.control.qp_terms import INF, rotation_error, skew, solve_qp, yaw_error
from gaitshift.control.wbc_data import Gains, TickInfo, TickReference

__all__ = ["Gains", "TickInfo", "TickReference", "WholeBodyController", "rotation_error"]


@dataclass
class _Frames:
    """The four task frames at the current state, in the order (left sole, right sole, torso, pelvis):
    Jacobians J (4, 6, nv) (linear then angular, at the sole centre / the body origin), velocities
    ``v = J qd`` (4, 6), ``Jdot qd`` (4, 6); sole centres (2, 3) and sole rotations (2, 3, 3)."""

    J: np.ndarray
    v: np.ndarray
    Jd: np.ndarray
    centre: np.ndarray
    R: list[np.ndarray]


class _Views:
    """Views into one ``MjData`` of what the controller reads, taken once (an attribute of ``MjData``
    builds a new array object at every access). That ``MjData`` is the controller's own, set from the
    estimated state (:mod:`gaitshift.sim.sensing`), never the plant's."""

    def __init__(self, data: mujoco.MjData, torso: int, pelvis: int) -> None:
        self.data = data
        self.qpos, self.qvel = data.qpos, data.qvel
        self.com, self.com_vel, self.L = data.subtree_com[0], data.subtree_linvel[0], data.subtree_angmom[0]
        self.bias, self.passive = data.qfrc_bias, data.qfrc_passive
        self.xpos, self.xmat = data.xpos, data.xmat
        self.torso_pos, self.pelvis_pos = data.xpos[torso], data.xpos[pelvis]
        self.torso_quat, self.pelvis_quat = data.xquat[torso], data.xquat[pelvis]


class WholeBodyController:
    """Inverse-dynamics QP for a floating-base robot with two multi-point soles (see module docstring).

    Args:
        plant: the compiled plant (anything with the attributes of :class:`PlantView`).
        posture: reference joint positions (nq,) (only the hinge entries are used).
        gains: task weights and gains.
    """

    def __init__(self, plant: PlantView, posture: np.ndarray, gains: Gains | None = None) -> None:
        self.plant = plant
        self.gains = gains or Gains()
        m = plant.model
        self.nv = m.nv
        self.nu = m.nu
        self.M = np.zeros((m.nv, m.nv))
        self.q_posture = posture[7:].copy()
        names = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, m.dof_jntid[d]) for d in plant.actuated_dofs]
        arms = set(plant.robot.arm_joints)
        self.arm = np.array([n in arms for n in names])
        self.n_points = [len(s.points) for s in plant.soles]
        knees = [names.index(k) for k in plant.robot.knees]  # (left, right)
        self.knee_dofs = plant.actuated_dofs[knees]
        self.knee_qadr = m.jnt_qposadr[m.dof_jntid[self.knee_dofs]]
        self.knee_range = m.jnt_range[m.dof_jntid[self.knee_dofs]]
        # per knee: its straight end is the lower end of its range (the end nearer 0), for the stance bound
        self._straight_low = [bool(abs(lo) <= abs(hi)) for lo, hi in self.knee_range]
        self.mass = plant.mass
        self.gravity = -float(m.opt.gravity[2])
        self.last_solver = "daqp"
        self._layouts: dict[tuple[int, ...], QpLayout] = {}
        self._cached_gains: Gains | None = None
        self._w_posture = self._w_diag = self._com_kp = self._com_kd = self._row_lim = np.zeros(0)
        self._J = np.zeros((4, 6, m.nv))
        self._Jdot = np.zeros((4, 6, m.nv))
        self._bodies = (plant.soles[0].body, plant.soles[1].body, plant.torso_body, plant.pelvis_body)
        dofs = np.concatenate([np.arange(6), plant.actuated_dofs])  # the dynamics and torque rows
        self._dofs: slice | np.ndarray = slice(None) if np.array_equal(dofs, np.arange(m.nv)) else dofs
        self._views: _Views | None = None
        # PD terms of the frame tasks, (4, 6) per frame (rows of _Frames): errors, velocity references,
        # feedforward accelerations; gains and weights (with the gains); rows in use per stance set
        self._err, self._vref, self._ff = np.zeros((4, 6)), np.zeros((4, 6)), np.zeros((4, 6))
        self._kp = self._kd = self._w_task = self._task_a = np.zeros((4, 6))
        self._task_rows: dict[tuple[int, ...], np.ndarray] = {}

    def _gain_arrays(self) -> None:
        """Per-dof posture weights, CoM gain vectors and the torque-row limits, recomputed when the
        gains object changes."""
        g = self.gains
        if self._cached_gains is g:
            return
        self._w_posture = np.where(self.arm, g.w_arm_posture, g.w_posture)
        self._w_diag = np.concatenate([np.zeros(6), self._w_posture]) + g.w_reg_qdd
        self._com_kp, self._com_kd = np.array(g.com_kp), np.array(g.com_kd)
        self._row_lim = np.concatenate([np.zeros(6), self.plant.torque_limit * g.torque_margin])
        sw, up = np.full(6, g.swing_kp), np.full(6, g.torso_kp)
        self._kp = np.array([sw, sw, up, up])
        self._kd = np.array([np.full(6, g.swing_kd)] * 2 + [np.full(6, g.torso_kd)] * 2)
        foot = [g.w_swing] * 3 + [g.w_swing_rot] * 3
        self._w_task = np.array([foot, foot, [0.0] * 3 + [g.w_torso] * 3, [0.0] * 3 + [g.w_pelvis] * 3])
        self._cached_gains = g

    def _view(self, data: mujoco.MjData) -> _Views:
        if self._views is None or self._views.data is not data:
            self._views = _Views(data, self.plant.torso_body, self.plant.pelvis_body)
        return self._views

    # ------------------------------------------------------------------ kinematics helpers
    def _frames(self, data: mujoco.MjData, vw: _Views) -> _Frames:
        """Jacobians, velocities and ``Jdot qd`` of the two soles, the torso and the pelvis."""
        p = self.plant
        m = p.model
        J, Jdot = self._J, self._Jdot
        c0, R0 = p.sole_frame(data, 0)
        c1, R1 = p.sole_frame(data, 1)
        points = (c0, c1, vw.torso_pos, vw.pelvis_pos)
        for i, body in enumerate(self._bodies):
            mujoco.mj_jac(m, data, J[i, :3], J[i, 3:], points[i], body)
            mujoco.mj_jacDot(m, data, Jdot[i, :3], Jdot[i, 3:], points[i], body)
        return _Frames(J, J @ vw.qvel, Jdot @ vw.qvel, np.array([c0, c1]), [R0, R1])

    def _contact_jacobian(self, stance: tuple[int, ...], fr: _Frames) -> tuple[np.ndarray, np.ndarray]:
        """Jacobian (3k, nv) of the k contact points of the stance soles and their positions (k, 3):
        ``J_i = J_lin - [r_i]x J_ang`` with r_i the point's offset from the sole centre."""
        if not stance:
            return np.zeros((0, self.nv)), np.zeros((0, 3))
        rows, points = [], []
        for s in stance:
            r = self.plant.soles[s].points @ fr.R[s].T
            rows.append(fr.J[s, :3] - skew(r) @ fr.J[s, 3:])
            points.append(fr.centre[s] + r)
        if len(stance) == 1:
            return rows[0].reshape(-1, self.nv), points[0]
        return np.concatenate(rows).reshape(-1, self.nv), np.concatenate(points)

    def _layout(self, stance: tuple[int, ...]) -> QpLayout:
        """The QP structure of ``stance`` (rebuilt when the assumed friction changes)."""
        lay = self._layouts.get(stance)
        if lay is None or lay.mu != self.gains.mu:
            lay = self._layouts[stance] = QpLayout.build(stance, self.n_points, self.nv, self.nu, self.gains.mu)
        return lay

    # ------------------------------------------------------------------ tasks
    def _centroidal_tasks(
        self, H: np.ndarray, f: np.ndarray, vw: _Views, ref: TickReference, points: np.ndarray, gram: np.ndarray
    ) -> None:
        """CoM (Newton) and angular-momentum damping (Euler about the CoM) on the contact forces, plus
        their regularisation: the (3k, 3k) force block of the cost."""
        g = self.gains
        k, nv = len(points), self.nv
        # the views are of the controller's own MjData (the estimated state, sim/sensing.py), never the plant's
        acc_des = ref.com_acc + self._com_kp * (ref.com_pos - vw.com) + self._com_kd * (ref.com_vel - vw.com_vel)
        acc_des[2] += self.gravity
        scale = self.mass * 0.1
        moment = skew(points - vw.com).transpose(1, 0, 2).reshape(3, 3 * k)  # [[r_1]x ... [r_k]x]
        Hf = (g.w_com / self.mass**2) * gram + (g.w_angmom / scale**2) * (moment.T @ moment)
        Hf.flat[:: 3 * k + 1] += g.w_reg_f
        H[nv:, nv:] = Hf
        f[nv:] = moment.T @ ((g.w_angmom * g.angmom_kd / scale**2) * vw.L)
        f[nv:].reshape(k, 3)[:] -= (g.w_com / self.mass) * acc_des

    def _motion_rows(self, vw: _Views, ref: TickReference, fr: _Frames) -> np.ndarray:
        """Swing-foot pose and torso and pelvis orientation: the PD targets of the four frames,
        ``a = K_p e + K_d (v_ref - J qd) - Jdot qd + a_ff`` (4, 6), and the indices of the rows in use
        among the 24 frame rows (position and orientation of the swing soles, orientation of the torso
        and the pelvis)."""
        stance = (bool(ref.stance[0]), bool(ref.stance[1]))
        rows = self._task_rows.get(stance)
        if rows is None:
            swing = [r for s in (0, 1) if not stance[s] for r in range(6 * s, 6 * s + 6)]
            rows = self._task_rows[stance] = np.array([*swing, 15, 16, 17, 21, 22, 23])
        err, vref, ff = self._err, self._vref, self._ff
        err[:2, :3] = ref.foot_pos - fr.centre
        vref[:2, :3] = ref.foot_vel
        vref[:2, 5] = ref.yaw_rate
        vref[2:, 5] = ref.torso_yaw_rate
        ff[:2, :3] = ref.foot_acc
        for s in (0, 1):
            if not stance[s]:
                quat = np.empty(4)
                mujoco.mju_mat2Quat(quat, fr.R[s].ravel())
                err[s, 3:] = yaw_error(ref.yaw[s], quat, ref.foot_pitch[s])  # sole on terrain
        err[2, 3:] = yaw_error(ref.torso_yaw, vw.torso_quat)
        err[3, 3:] = yaw_error(ref.torso_yaw, vw.pelvis_quat)
        self._task_a = self._kp * err + self._kd * (vref - fr.v) - fr.Jd + ff
        return rows

    def _motion_tasks(self, H: np.ndarray, f: np.ndarray, vw: _Views, fr: _Frames, rows: np.ndarray) -> None:
        """The (nv, nv) qdd block of the cost: the stacked task rows, posture (joint PD toward the
        standing pose) and regularisation on the diagonal."""
        g = self.gains
        nv = self.nv
        J, w = fr.J.reshape(24, nv)[rows], self._w_task.ravel()[rows]
        Jw = J.T * w
        Hq = Jw @ J
        Hq.flat[:: nv + 1] += self._w_diag
        H[:nv, :nv] = Hq
        a_post = g.posture_kp * (self.q_posture - vw.qpos[7:]) - g.posture_kd * vw.qvel[6:]
        f[:nv] = Jw @ self._task_a.ravel()[rows]
        f[6:nv] += self._w_posture * a_post
        f[:nv] *= -1.0

    # ------------------------------------------------------------------ constraints
    def _constraints(self, lay: QpLayout, h: np.ndarray, Jc: np.ndarray, fr: _Frames, ref: TickReference) -> None:
        """Refill the changing rows of ``lay``: floating-base dynamics and torque limits (one block,
        ``[M, -Jc^T]`` at the base and actuated dofs), non-sliding feet, force caps
        (:mod:`gaitshift.control.qp_layout`)."""
        nv, A = self.nv, lay.A
        r = slice(0, lay.rows["torque"].stop)
        A[r, :nv] = self.M[self._dofs]
        np.negative(Jc.T[self._dofs], out=A[r, nv:])
        h_rows = h[self._dofs]
        np.subtract(self._row_lim, h_rows, out=lay.up["dynamics+torque"])
        np.subtract(-self._row_lim, h_rows, out=lay.lo["dynamics+torque"])
        if lay.stance:
            lay.up["cap"][:] = ref.fz_max[lay.feet]
            A[lay.rows["feet"], :nv] = fr.J[lay.feet].reshape(-1, nv)
            b = (-fr.Jd[lay.feet] - self.gains.stance_kv * fr.v[lay.feet]).ravel()
            lay.up["feet"][:] = b
            lay.lo["feet"][:] = b

    def _knee_bounds(self, vw: _Views, ref: TickReference, lay: QpLayout) -> None:
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
        for s in (0, 1):
            drift = float(vw.qpos[self.knee_qadr[s]]) + float(vw.qvel[self.knee_dofs[s]]) * T
            lo = 2.0 * (float(self.knee_range[s, 0]) + g.limit_margin - drift) / T**2
            hi = 2.0 * (float(self.knee_range[s, 1]) - g.limit_margin - drift) / T**2
            if ref.stance[s]:  # the straight knee is the end of the range nearer 0
                lo, hi = (lo, INF) if self._straight_low[s] else (-INF, hi)
            lay.lo["x"][self.knee_dofs[s]], lay.up["x"][self.knee_dofs[s]] = min(lo, hi), max(lo, hi)

    def _free_knees(self, lay: QpLayout) -> None:
        """No bounds on the knee accelerations."""
        for dof in self.knee_dofs:
            lay.lo["x"][dof], lay.up["x"][dof] = -INF, INF

    def _solve(self, H: np.ndarray, f: np.ndarray, lay: QpLayout) -> np.ndarray | None:
        """The QP solution x, or None (:func:`gaitshift.control.qp_terms.solve_qp`)."""
        x, self.last_solver = solve_qp(H, f, lay.A, lay.bu, lay.bl, lay.sense)
        return x  # type: ignore[no-any-return]

    # ------------------------------------------------------------------ the QP
    def compute(self, data: mujoco.MjData, ref: TickReference) -> tuple[np.ndarray, TickInfo]:
        """Torques (nu,) for the current state. ``data`` must hold the forward quantities
        (``mj_forward`` or ``mj_step1``) and ``mj_subtreeVel``."""
        p = self.plant
        nv = self.nv
        vw = self._view(data)
        mujoco.mj_fullM(p.model, data, self.M)
        h = vw.bias - vw.passive
        stance = tuple(s for s in (0, 1) if ref.stance[s])
        lay = self._layout(stance)
        H = np.zeros((lay.n, lay.n))
        f = np.zeros(lay.n)
        self._gain_arrays()
        fr = self._frames(data, vw)
        Jc, points = self._contact_jacobian(stance, fr)
        if len(points):
            self._centroidal_tasks(H, f, vw, ref, points, lay.gram_f)
        self._motion_tasks(H, f, vw, fr, self._motion_rows(vw, ref, fr))
        self._constraints(lay, h, Jc, fr, ref)
        x = None
        if self.gains.limit_horizon > 0:  # with the knee-limit bounds, then without if infeasible
            self._knee_bounds(vw, ref, lay)
            x = self._solve(H, f, lay)
            self._free_knees(lay)
        if x is None:
            x = self._solve(H, f, lay)
        info = TickInfo(ok=x is not None, solver=self.last_solver)
        Sa = p.actuated_dofs
        if x is None:
            # infeasible: drop the stance and torque constraints' coupling, keep posture (safe fallback)
            lim = p.torque_limit * self.gains.torque_margin
            qj, vj = vw.qpos[7:], vw.qvel[6:]
            tau = np.clip(self.gains.posture_kp * 0.5 * (self.q_posture - qj) - 2.0 * vj + h[Sa], -lim, lim)
            return tau, info
        qdd, fc = x[:nv], x[nv:]
        tau = lay.A[lay.rows["torque"]] @ x + h[Sa]  # M_a qdd + h_a - J_a^T f
        forces = np.zeros((2, 3))
        start = 0
        for s in stance:
            k = self.n_points[s]
            forces[s] = fc[3 * start : 3 * (start + k)].reshape(k, 3).sum(axis=0)
            start += k
        info.forces = forces
        info.qdd, info.contact_forces, info.contact_jacobian = qdd, fc, Jc
        return np.minimum(np.maximum(tau, -p.torque_limit), p.torque_limit), info
