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
:mod:`gaitshift.control.qp_terms`.

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
from typing import Any

import mujoco
import numpy as np

from gaitshift.common.rotations import rot_y, rot_z
from gaitshift.control.plant_view import PlantView
from gaitshift.control.qp_terms import add_task, friction_rows, rotation_error, skew, solve_qp
from gaitshift.control.wbc_data import Gains, TickInfo, TickReference

__all__ = ["Gains", "TickInfo", "TickReference", "WholeBodyController", "rotation_error"]


@dataclass
class _Feet:
    """Both sole frames at the current state: Jacobians (6, nv) (linear then angular), Jdot qd (6,),
    centres (3,) and rotations (3, 3), indexed by side."""

    J: list[np.ndarray]
    Jd: list[np.ndarray]
    centre: list[np.ndarray]
    R: list[np.ndarray]


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
        self._jp = np.zeros((3, m.nv))
        self._jr = np.zeros((3, m.nv))
        self._jpd = np.zeros((3, m.nv))
        self._jrd = np.zeros((3, m.nv))
        self.S = np.zeros((m.nu, m.nv))
        self.S[np.arange(m.nu), plant.actuated_dofs] = 1.0
        names = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, m.dof_jntid[d]) for d in plant.actuated_dofs]
        arms = set(plant.robot.arm_joints)
        self.arm = np.array([n in arms for n in names])
        self.n_points = [len(s.points) for s in plant.soles]
        knees = [names.index(k) for k in plant.robot.knees]  # (left, right)
        self.knee_dofs = plant.actuated_dofs[knees]
        self.knee_qadr = m.jnt_qposadr[m.dof_jntid[self.knee_dofs]]
        self.knee_range = m.jnt_range[m.dof_jntid[self.knee_dofs]]
        self.mass = plant.mass
        self.gravity = -float(m.opt.gravity[2])
        self.last_solver = "daqp"

    # ------------------------------------------------------------------ kinematics helpers
    def _frame_jac(self, data: mujoco.MjData, body: int, point: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(J (6, nv), Jdot qd (6,)) of a point fixed on ``body`` (linear then angular)."""
        m = self.plant.model
        mujoco.mj_jac(m, data, self._jp, self._jr, point, body)
        mujoco.mj_jacDot(m, data, self._jpd, self._jrd, point, body)
        J = np.vstack([self._jp, self._jr])
        Jd = np.concatenate([self._jpd @ data.qvel, self._jrd @ data.qvel])
        return J, Jd

    def _feet(self, data: mujoco.MjData) -> _Feet:
        feet = _Feet([], [], [], [])
        for s in (0, 1):
            c, R = self.plant.sole_frame(data, s)
            J, Jd = self._frame_jac(data, self.plant.soles[s].body, c)
            feet.J.append(J)
            feet.Jd.append(Jd)
            feet.centre.append(c)
            feet.R.append(R)
        return feet

    def _contact_jacobian(self, stance: list[int], feet: _Feet) -> tuple[np.ndarray, np.ndarray]:
        """Jacobian (3k, nv) of the k contact points of the stance soles and their positions (k, 3)."""
        p = self.plant
        rows, points = [], []
        for s in stance:
            pts = feet.centre[s] + p.soles[s].points @ feet.R[s].T
            for pt in pts:
                rows.append(feet.J[s][:3] - skew(pt - feet.centre[s]) @ feet.J[s][3:])
            points.append(pts)
        if not rows:
            return np.zeros((0, self.nv)), np.zeros((0, 3))
        return np.vstack(rows), np.vstack(points)

    # ------------------------------------------------------------------ tasks
    def _centroidal_tasks(
        self, P: np.ndarray, qv: np.ndarray, data: mujoco.MjData, ref: TickReference, points: np.ndarray
    ) -> None:
        """CoM (Newton) and angular-momentum damping (Euler about the CoM) on the contact forces."""
        g = self.gains
        k = len(points)
        # ``data`` is the controller's own MjData (the estimated state, sim/sensing.py), never the plant's
        com = data.subtree_com[0].copy()
        com_vel = data.subtree_linvel[0].copy()
        L = data.subtree_angmom[0].copy()
        fcols = slice(self.nv, self.nv + 3 * k)
        sumF = np.tile(np.eye(3), (1, k)) / self.mass
        acc_des = (
            ref.com_acc
            + np.array(g.com_kp) * (ref.com_pos - com)
            + np.array(g.com_kd) * (ref.com_vel - com_vel)
            + np.array([0, 0, self.gravity])
        )
        add_task(P, qv, sumF, acc_des, g.w_com, fcols)
        moment = np.hstack([skew(pt - com) for pt in points]) / (self.mass * 0.1)
        add_task(P, qv, moment, -g.angmom_kd * L / (self.mass * 0.1), g.w_angmom, fcols)
        add_task(P, qv, np.eye(3 * k), np.zeros(3 * k), g.w_reg_f, fcols)

    def _motion_tasks(
        self, P: np.ndarray, qv: np.ndarray, data: mujoco.MjData, ref: TickReference, feet: _Feet
    ) -> None:
        """Swing-foot pose, torso and pelvis orientation, posture and regularisation on qdd."""
        g = self.gains
        p = self.plant
        nv = self.nv
        qd = data.qvel
        qcols = slice(0, nv)
        for s in (0, 1):
            if ref.stance[s]:
                continue
            e = ref.foot_pos[s] - feet.centre[s]
            ed = ref.foot_vel[s] - feet.J[s][:3] @ qd
            a = ref.foot_acc[s] + g.swing_kp * e + g.swing_kd * ed - feet.Jd[s][:3]
            add_task(P, qv, feet.J[s][:3], a, g.w_swing, qcols)
            er = rotation_error(rot_z(ref.yaw[s]) @ rot_y(-ref.foot_pitch[s]), feet.R[s])  # sole on terrain
            w_ref = np.array([0.0, 0.0, ref.yaw_rate[s]])
            ar = g.swing_kp * er + g.swing_kd * (w_ref - feet.J[s][3:] @ qd) - feet.Jd[s][3:]
            add_task(P, qv, feet.J[s][3:], ar, g.w_swing_rot, qcols)
        R_yaw = rot_z(ref.torso_yaw)
        w_torso = np.array([0.0, 0.0, ref.torso_yaw_rate])
        for body, w in ((p.torso_body, g.w_torso), (p.pelvis_body, g.w_pelvis)):
            J, Jd = self._frame_jac(data, body, data.xpos[body])
            er = rotation_error(R_yaw, data.xmat[body].reshape(3, 3))
            a = g.torso_kp * er + g.torso_kd * (w_torso - J[3:] @ qd) - Jd[3:]
            add_task(P, qv, J[3:], a, w, qcols)
        qj, vj = data.qpos[7:], qd[6:]
        a_post = g.posture_kp * (self.q_posture - qj) - g.posture_kd * vj
        wp = np.where(self.arm, g.w_arm_posture, g.w_posture)
        P[6:nv, 6:nv] += np.diag(wp)
        qv[6:nv] -= wp * a_post
        P[:nv, :nv] += g.w_reg_qdd * np.eye(nv)

    # ------------------------------------------------------------------ constraints
    def _equalities(
        self, data: mujoco.MjData, M: np.ndarray, h: np.ndarray, Jc: np.ndarray, stance: list[int], feet: _Feet
    ) -> tuple[np.ndarray, np.ndarray]:
        """Floating-base rows of the equations of motion and non-sliding stance feet: (A, b)."""
        k3 = Jc.shape[0]
        qd = data.qvel
        A_eq = [np.hstack([M[:6], -Jc.T[:6]])]
        b_eq = [-h[:6]]
        for s in stance:
            v = feet.J[s] @ qd
            A_eq.append(np.hstack([feet.J[s], np.zeros((6, k3))]))
            b_eq.append(-feet.Jd[s] - self.gains.stance_kv * v)
        return np.vstack(A_eq), np.concatenate(b_eq)

    def _inequalities(
        self, M: np.ndarray, h: np.ndarray, Jc: np.ndarray, stance: list[int], ref: TickReference
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Torque limits, friction pyramids and per-foot normal-force caps: (G, h, lb, ub) with G x <= h."""
        g = self.gains
        p = self.plant
        nv = self.nv
        k = Jc.shape[0] // 3
        n = nv + 3 * k
        lim = p.torque_limit * g.torque_margin
        Sa = p.actuated_dofs
        T = np.hstack([M[Sa], -Jc.T[Sa]])
        G = [T, -T]
        hh = [lim - h[Sa], lim + h[Sa]]
        lb = np.full(n, -np.inf)
        ub = np.full(n, np.inf)
        if k:
            lb[nv + 2 :: 3] = 0.0
            cap = np.zeros((len(stance), n))
            start = nv
            for j, s in enumerate(stance):
                cap[j, start + 2 : start + 3 * self.n_points[s] : 3] = 1.0
                start += 3 * self.n_points[s]
            G += [friction_rows(n, k, nv, g.mu), cap]
            hh += [np.zeros(4 * k), ref.fz_max[stance]]
        return np.vstack(G), np.concatenate(hh), lb, ub

    def _knee_bounds(
        self, data: mujoco.MjData, ref: TickReference, lb: np.ndarray, ub: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Bounds on the swinging knees' accelerations that keep them ``limit_margin`` inside their
        range over ``limit_horizon`` s: ``q + v T + a T^2 / 2`` within the range. Without them the
        trailing knee of a fast running swing is driven straight into its limit just after lift-off
        (docs/simulation.md, "Top speed")."""
        g = self.gains
        T = g.limit_horizon
        qk, vk = data.qpos[self.knee_qadr], data.qvel[self.knee_dofs]
        lo = 2.0 * (self.knee_range[:, 0] + g.limit_margin - qk - vk * T) / T**2
        hi = 2.0 * (self.knee_range[:, 1] - g.limit_margin - qk - vk * T) / T**2
        swing = ~np.asarray(ref.stance, bool)
        lb, ub = lb.copy(), ub.copy()
        lb[self.knee_dofs[swing]] = np.minimum(lo, hi)[swing]
        ub[self.knee_dofs[swing]] = np.maximum(lo, hi)[swing]
        return lb, ub

    def _solve(self, cost: tuple[np.ndarray, np.ndarray], ineq: Any, eq: tuple[np.ndarray, np.ndarray]) -> Any:
        """The QP solution x, or None (:func:`gaitshift.control.qp_terms.solve_qp`)."""
        x, self.last_solver = solve_qp(cost, ineq, eq)
        return x

    # ------------------------------------------------------------------ the QP
    def compute(self, data: mujoco.MjData, ref: TickReference) -> tuple[np.ndarray, TickInfo]:
        """Torques (nu,) for the current state. ``data`` must hold the forward quantities
        (``mj_forward`` or ``mj_step1``) and ``mj_subtreeVel``."""
        p = self.plant
        nv = self.nv
        mujoco.mj_fullM(p.model, data, self.M)
        M = self.M
        h = data.qfrc_bias - data.qfrc_passive
        stance = [s for s in (0, 1) if ref.stance[s]]
        n = nv + 3 * sum(self.n_points[s] for s in stance)
        P = np.zeros((n, n))
        qv = np.zeros(n)
        feet = self._feet(data)
        Jc, points = self._contact_jacobian(stance, feet)
        if len(points):
            self._centroidal_tasks(P, qv, data, ref, points)
        self._motion_tasks(P, qv, data, ref, feet)
        ineq = self._inequalities(M, h, Jc, stance, ref)
        eq = self._equalities(data, M, h, Jc, stance, feet)
        x = None
        if self.gains.limit_horizon > 0:  # with the knee-limit bounds, then without if infeasible
            G, hh, lb, ub = ineq
            x = self._solve((P, qv), (G, hh, *self._knee_bounds(data, ref, lb, ub)), eq)
        if x is None:
            x = self._solve((P, qv), ineq, eq)
        info = TickInfo(ok=x is not None, solver=self.last_solver)
        Sa = p.actuated_dofs
        if x is None:
            # infeasible: drop the stance and torque constraints' coupling, keep posture (safe fallback)
            lim = p.torque_limit * self.gains.torque_margin
            qj, vj = data.qpos[7:], data.qvel[6:]
            tau = np.clip(self.gains.posture_kp * 0.5 * (self.q_posture - qj) - 2.0 * vj + h[Sa], -lim, lim)
            return tau, info
        qdd, f = x[:nv], x[nv:]
        tau = M[Sa] @ qdd + h[Sa] - Jc.T[Sa] @ f
        forces = np.zeros((2, 3))
        start = 0
        for s in stance:
            k = self.n_points[s]
            forces[s] = f[3 * start : 3 * (start + k)].reshape(k, 3).sum(axis=0)
            start += k
        info.forces = forces
        info.qdd, info.contact_forces, info.contact_jacobian = qdd, f, Jc
        return np.clip(tau, -p.torque_limit, p.torque_limit), info
