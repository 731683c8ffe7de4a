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
      forces at the sole's contact points, each in its friction pyramid ``|f_x|, |f_y| <= mu f_z``
      (sole axes), can exert; this holds the CoP inside the sole and bounds the yaw moment. The faces
      are those of the points' own cone (a rectangle's are Caron's 16 rows; the G1's trapezoid has 28);
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

from gaitshift.control.plant_view import PlantView
from gaitshift.control.qp_layout import QpLayout
from gaitshift.control.qp_terms import INF, SKEW_BASIS, rotation_error, solve_qp, yaw_error
from gaitshift.control.wbc_data import Gains, TickInfo, TickReference
from gaitshift.control.wrench_cone import SoleCone

__all__ = ["Gains", "TickInfo", "TickReference", "WholeBodyController", "rotation_error"]


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
        self.torso_quat, self.pelvis_quat = data.xquat[torso], data.xquat[pelvis]


class _Stance:
    """What one stance set (left, right in stance) fixes for the current gains: the QP layout, the
    frame-task rows in use among the 24 (position and orientation of the swing soles, orientation of
    the torso and the pelvis) and their weights, the swing sides, and the wrench regularisation blocks
    ``w_reg_f Q`` of the stance soles as (ns, 2, 2, 3, 3) (force/torque blocks)."""

    def __init__(self, lay: QpLayout, key: tuple[bool, bool], w_task: np.ndarray, w_reg: float) -> None:
        self.lay = lay
        self.swing = tuple(s for s in (0, 1) if not key[s])
        self.rows = np.array([r for s in self.swing for r in range(6 * s, 6 * s + 6)] + [15, 16, 17, 21, 22, 23])
        self.w_rows = w_task.ravel()[self.rows]
        self.reg = np.array([w_reg * c.metric.reshape(2, 3, 2, 3).transpose(0, 2, 1, 3) for c in lay.cones])
        self.faces = [c.faces.reshape(-1, 2, 3) for c in lay.cones]


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
        self.mass = plant.mass
        self.gravity = -float(m.opt.gravity[2])
        self.last_solver = "daqp"
        self._cones: dict[float, tuple[SoleCone, SoleCone]] = {}
        self._stances: dict[tuple[bool, bool], _Stance] = {}
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
        self._offset = np.zeros((4, 3, 1))
        self._offset[:2, :, 0] = [s.centre for s in soles]
        self._sole_rot = np.array([s.rotation for s in soles])
        self._J, self._Jdot = np.zeros((4, 6, m.nv)), np.zeros((4, 6, m.nv))
        self._v, self._Jd = np.zeros((4, 6)), np.zeros((4, 6))
        self._P, self._R = np.zeros((4, 3)), np.zeros((2, 3, 3))
        # PD terms of the frame tasks (4, 6): errors, velocity references, feedforward accelerations
        self._err, self._vref, self._ff = np.zeros((4, 6)), np.zeros((4, 6)), np.zeros((4, 6))
        self._t = np.zeros(6)  # centroidal target: [m cdd_des; -K_L L]
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
        self._weight = np.array([0.0, 0.0, self.mass * self.gravity])
        self._row_lim = np.concatenate([np.zeros(6), self.plant.torque_limit * g.torque_margin])
        self._neg_row_lim = -self._row_lim
        scale = self.mass * 0.1
        self._w_cent = np.array([g.w_com / self.mass**2] * 3 + [g.w_angmom / scale**2] * 3)
        sw, up = np.full(6, g.swing_kp), np.full(6, g.torso_kp)
        self._kp = np.array([sw, sw, up, up])
        self._kd = np.array([np.full(6, g.swing_kd)] * 2 + [np.full(6, g.torso_kd)] * 2)
        foot = [g.w_swing] * 3 + [g.w_swing_rot] * 3
        self._w_task = np.array([foot, foot, [0.0] * 3 + [g.w_torso] * 3, [0.0] * 3 + [g.w_pelvis] * 3])
        self._stances.clear()
        self._cached_gains = g

    def _view(self, data: mujoco.MjData) -> _Views:
        if self._views is None or self._views.data is not data:
            self._views = _Views(data, self.plant.torso_body, self.plant.pelvis_body)
        return self._views

    def _stance(self, ref: TickReference) -> _Stance:
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
            st = self._stances[key] = _Stance(lay, key, self._w_task, self.gains.w_reg_f)
        return st

    # ------------------------------------------------------------------ kinematics
    def _frames(self, data: mujoco.MjData, vw: _Views) -> None:
        """Points, sole rotations, Jacobians, velocities and ``Jdot qd`` of the two soles, the torso and
        the pelvis (one gather of the four bodies' poses, one pass of ``mj_jac``/``mj_jacDot``)."""
        m = self.plant.model
        Rb = vw.xmat[self._bodies].reshape(4, 3, 3)
        np.add(vw.xpos[self._bodies], (Rb @ self._offset)[..., 0], out=self._P)
        np.matmul(Rb[:2], self._sole_rot, out=self._R)
        J, Jdot, P = self._J, self._Jdot, self._P
        for i, body in enumerate(self._body_ids):
            mujoco.mj_jac(m, data, J[i, :3], J[i, 3:], P[i], body)
            mujoco.mj_jacDot(m, data, Jdot[i, :3], Jdot[i, 3:], P[i], body)
        np.matmul(J, vw.qvel, out=self._v)
        np.matmul(Jdot, vw.qvel, out=self._Jd)

    # ------------------------------------------------------------------ tasks
    def _centroidal_tasks(self, vw: _Views, ref: TickReference, st: _Stance) -> None:
        """CoM (Newton) and angular-momentum damping (Euler about the CoM) on the contact wrenches,
        plus their regularisation: the (6 ns, 6 ns) wrench block of the cost."""
        lay, nv = st.lay, self.nv
        ns = len(lay.stance)
        d = self._P[lay.feet] - vw.com
        lay.Ac_skew[:] = (d @ SKEW_BASIS).reshape(ns, 3, 3)
        # the views are of the controller's own MjData (the estimated state, sim/sensing.py), never the plant's
        t = self._t
        t[:3] = (
            self.mass * ref.com_acc
            + self._com_kp * (ref.com_pos - vw.com)
            + self._com_kd * (ref.com_vel - vw.com_vel)
            + self._weight
        )
        np.multiply(vw.L, -self.gains.angmom_kd, out=t[3:])
        Aw = lay.Ac.T * self._w_cent
        np.matmul(Aw, lay.Ac, out=lay.H[nv:, nv:])
        np.matmul(Aw, t, out=lay.f[nv:])
        np.negative(lay.f[nv:], out=lay.f[nv:])
        R = self._R[lay.feet, None, None]
        lay.H_feet += R @ st.reg @ R.transpose(0, 1, 2, 4, 3)

    def _motion_targets(self, vw: _Views, ref: TickReference, st: _Stance) -> np.ndarray:
        """Swing-foot pose and torso and pelvis orientation: the PD targets of the four frames,
        ``a = K_p e + K_d (v_ref - J qd) - Jdot qd + a_ff`` (4, 6)."""
        err, vref, ff = self._err, self._vref, self._ff
        np.subtract(ref.foot_pos, self._P[:2], out=err[:2, :3])
        vref[:2, :3] = ref.foot_vel
        vref[:2, 5] = ref.yaw_rate
        vref[2:, 5] = ref.torso_yaw_rate
        ff[:2, :3] = ref.foot_acc
        for s in st.swing:
            quat = np.empty(4)
            mujoco.mju_mat2Quat(quat, self._R[s].ravel())
            yaw_error(ref.yaw[s], quat, ref.foot_pitch[s], out=err[s, 3:])  # sole on terrain
        yaw_error(ref.torso_yaw, vw.torso_quat, out=err[2, 3:])
        yaw_error(ref.torso_yaw, vw.pelvis_quat, out=err[3, 3:])
        a: np.ndarray = self._kp * err + self._kd * (vref - self._v) - self._Jd + ff
        return a

    def _motion_tasks(self, vw: _Views, ref: TickReference, st: _Stance) -> None:
        """The (nv, nv) qdd block of the cost: the stacked task rows, posture (joint PD toward the
        standing pose) and regularisation on the diagonal."""
        lay, nv = st.lay, self.nv
        a = self._motion_targets(vw, ref, st)
        Jr = self._J.reshape(24, nv)[st.rows]
        Jw = Jr.T * st.w_rows
        np.matmul(Jw, Jr, out=lay.H[:nv, :nv])
        lay.H_diag += self._w_diag
        fq = lay.f[:nv]
        np.matmul(Jw, a.ravel()[st.rows], out=fq)
        np.negative(fq, out=fq)
        fq[6:] += self._post_q * vw.qpos[7:] + self._post_v * vw.qvel[6:] + self._post_0

    # ------------------------------------------------------------------ constraints
    def _constraints(self, st: _Stance, h: np.ndarray, ref: TickReference) -> None:
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
        np.multiply(self._v[lay.feet].ravel(), -self.gains.stance_kv, out=b)
        b -= self._Jd[lay.feet].ravel()
        lay.lo["feet"][:] = b
        lay.up["cap"][:] = ref.fz_max[lay.feet]
        for j, s in enumerate(lay.stance):
            np.matmul(st.faces[j], self._R[s].T, out=lay.cone[j])

    def _knee_bounds(self, vw: _Views, ref: TickReference, lay: QpLayout) -> None:
        """Bounds on the swinging knees' accelerations that keep them ``limit_margin`` inside their
        range over ``limit_horizon`` s: ``q + v T + a T^2 / 2`` within the range. Without them the
        trailing knee of a fast running swing is driven straight into its limit just after lift-off
        (docs/simulation.md, "Top speed")."""
        g = self.gains
        T = g.limit_horizon
        for s in (0, 1):
            if ref.stance[s]:
                continue
            drift = float(vw.qpos[self.knee_qadr[s]]) + float(vw.qvel[self.knee_dofs[s]]) * T
            lo = 2.0 * (float(self.knee_range[s, 0]) + g.limit_margin - drift) / T**2
            hi = 2.0 * (float(self.knee_range[s, 1]) - g.limit_margin - drift) / T**2
            lay.lo["x"][self.knee_dofs[s]], lay.up["x"][self.knee_dofs[s]] = min(lo, hi), max(lo, hi)

    def _free_knees(self, lay: QpLayout) -> None:
        """No bounds on the knee accelerations."""
        lay.lo["x"][self.knee_dofs] = -INF
        lay.up["x"][self.knee_dofs] = INF

    def _solve(self, lay: QpLayout) -> np.ndarray | None:
        """The QP solution x, or None (:func:`gaitshift.control.qp_terms.solve_qp`)."""
        x, self.last_solver = solve_qp(lay.H, lay.f, lay.A, lay.bu, lay.bl, lay.sense)
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
        st = self._stance(ref)
        lay = st.lay
        self._frames(data, vw)
        if lay.stance:
            self._centroidal_tasks(vw, ref, st)
        self._motion_tasks(vw, ref, st)
        self._constraints(st, h, ref)
        x = None
        if self.gains.limit_horizon > 0 and st.swing:  # with the knee-limit bounds, then without if infeasible
            self._knee_bounds(vw, ref, lay)
            x = self._solve(lay)
            self._free_knees(lay)
        if x is None:
            x = self._solve(lay)
        info = TickInfo(ok=x is not None, solver=self.last_solver)
        if x is None:
            # infeasible: drop the stance and torque constraints' coupling, keep posture (safe fallback)
            lim = p.torque_limit * self.gains.torque_margin
            qj, vj = vw.qpos[7:], vw.qvel[6:]
            tau = np.clip(self.gains.posture_kp * 0.5 * (self.q_posture - qj) - 2.0 * vj + h[self._act], -lim, lim)
            return tau, info
        tau = lay.A[lay.rows["torque"]] @ x + h[self._act]  # M_a qdd + h_a - J_a^T w
        w = x[nv:]
        for j, s in enumerate(lay.stance):
            info.forces[s] = w[6 * j : 6 * j + 3]
        info.qdd, info.contact_wrenches = x[:nv], w
        info.contact_jacobian = self._J[lay.feet].reshape(-1, nv).copy()
        return np.clip(tau, -p.torque_limit, p.torque_limit), info
