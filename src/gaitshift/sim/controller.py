"""Whole-body inverse-dynamics QP, solved once per control tick (docs/simulation.md).

Model, from MuJoCo's own quantities at the current state (``M = mj_fullM``, ``h = qfrc_bias -
qfrc_passive``, Jacobians ``mj_jac``/``mj_jacDot``)::

    M qdd + h = S^T tau + sum_i Jp_i^T f_i                                  (1)

with ``f_i`` the force at contact point i (the lowest points of the four sole spheres of each stance
foot, world frame). Unknowns ``x = [qdd (nv), f (3k)]``; the torques are the affine function
``tau = S (M qdd + h - Jc^T f)`` of them, so torque limits are linear inequalities in x. Eliminating
tau this way is exact and keeps the QP at nv + 3k variables (35 + 24 for the G1 in double support).

Hard constraints:
    * floating-base rows of (1) (6 equations);
    * non-sliding stance feet: ``J_foot qdd + Jdot_foot qd = -K_v v_foot`` (6 per stance foot);
    * friction pyramids ``|f_x|, |f_y| <= mu f_z`` and unilateral ``f_z >= 0`` per point; the CoP of a
      foot is then inside the convex hull of its four points, i.e. inside the sole;
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

from dataclasses import dataclass, field

import mujoco
import numpy as np
import qpsolvers

from .plant import Plant

GRAVITY = np.array([0.0, 0.0, -9.81])


@dataclass(frozen=True)
class Gains:
    """Task weights and PD gains of the whole-body QP."""

    com_kp: tuple[float, float, float] = (60.0, 60.0, 300.0)
    com_kd: tuple[float, float, float] = (16.0, 16.0, 35.0)
    w_com: float = 100.0
    w_angmom: float = 2.0
    angmom_kd: float = 10.0
    swing_kp: float = 900.0
    swing_kd: float = 60.0
    w_swing: float = 100.0
    w_swing_rot: float = 3.0
    torso_kp: float = 200.0
    torso_kd: float = 30.0
    w_torso: float = 0.5
    w_pelvis: float = 1.0
    posture_kp: float = 100.0
    posture_kd: float = 20.0
    w_posture: float = 0.002
    w_arm_posture: float = 0.3
    w_reg_qdd: float = 1e-5
    w_reg_f: float = 1e-6
    mu: float = 0.45
    stance_kv: float = 20.0
    torque_margin: float = 0.98


@dataclass
class TickReference:
    """What the controller tracks at one tick (world frame, SI).

    ``stance``: feet whose contact points carry force and are held still. ``fz_max``: per-foot cap on
    the total normal force, N (force ramp). ``foot_*``: sole-centre references (2, 3); used for feet
    not in stance. ``yaw``: (2,) foot yaws; ``torso_yaw``: heading of pelvis and torso.
    """

    com_pos: np.ndarray
    com_vel: np.ndarray
    com_acc: np.ndarray
    stance: np.ndarray
    fz_max: np.ndarray
    foot_pos: np.ndarray
    foot_vel: np.ndarray
    foot_acc: np.ndarray
    yaw: np.ndarray
    torso_yaw: float = 0.0


@dataclass
class TickInfo:
    """Diagnostics of one solve."""

    ok: bool = True
    solver: str = "daqp"
    forces: np.ndarray = field(default_factory=lambda: np.zeros((2, 3)))
    qdd: np.ndarray | None = None
    contact_forces: np.ndarray | None = None   # (3k,) world-frame point forces
    contact_jacobian: np.ndarray | None = None  # (3k, nv)


def _skew(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def _rot_z(yaw: float) -> np.ndarray:
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rotation_error(R_ref: np.ndarray, R: np.ndarray) -> np.ndarray:
    """World-frame rotation vector e with exp([e]) R = R_ref, rad, (3,)."""
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, (R_ref @ R.T).ravel())
    e = np.empty(3)
    mujoco.mju_quat2Vel(e, quat, 1.0)
    return e


class WholeBodyController:
    """Inverse-dynamics QP for the G1 (see module docstring).

    Args:
        plant: the compiled plant.
        posture: reference joint positions (nq,) (only the hinge entries are used).
        gains: task weights and gains.
    """

    def __init__(self, plant: Plant, posture: np.ndarray, gains: Gains | None = None) -> None:
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
        self.arm = np.array(["shoulder" in n or "elbow" in n or "wrist" in n for n in names])
        self.mass = plant.mass
        self.gravity = -float(m.opt.gravity[2])
        self.last_solver = "daqp"

    # ------------------------------------------------------------------ kinematics helpers
    def _frame_jac(self, data: mujoco.MjData, body: int, point: np.ndarray):
        """(J (6, nv), Jdot qd (6,)) of a point fixed on ``body`` (linear then angular)."""
        m = self.plant.model
        mujoco.mj_jac(m, data, self._jp, self._jr, point, body)
        mujoco.mj_jacDot(m, data, self._jpd, self._jrd, point, body)
        J = np.vstack([self._jp, self._jr])
        Jd = np.concatenate([self._jpd @ data.qvel, self._jrd @ data.qvel])
        return J, Jd

    # ------------------------------------------------------------------ the QP
    def compute(self, data: mujoco.MjData, ref: TickReference) -> tuple[np.ndarray, TickInfo]:
        """Torques (nu,) for the current state. ``data`` must hold the forward quantities
        (``mj_forward`` or ``mj_step1``) and ``mj_subtreeVel``."""
        g = self.gains
        p = self.plant
        m = p.model
        nv = self.nv
        mujoco.mj_fullM(m, data, self.M)
        M = self.M
        h = data.qfrc_bias - data.qfrc_passive
        qd = data.qvel
        com = data.subtree_com[0].copy()
        com_vel = data.subtree_linvel[0].copy()
        L = data.subtree_angmom[0].copy()

        stance = [s for s in (0, 1) if ref.stance[s]]
        k = 4 * len(stance)
        n = nv + 3 * k

        P = np.zeros((n, n))
        qv = np.zeros(n)

        def add(A, b, w, cols=slice(0, None)):
            P[cols, cols] += w * A.T @ A
            qv[cols] -= w * A.T @ b

        foot_J, foot_Jd, foot_c, foot_R = [], [], [], []
        for s in (0, 1):
            c, R = p.sole_frame(data, s)
            J, Jd = self._frame_jac(data, p.soles[s].body, c)
            foot_J.append(J)
            foot_Jd.append(Jd)
            foot_c.append(c)
            foot_R.append(R)

        # contact Jacobian (3k, nv) and point lever arms
        Jc = np.zeros((3 * k, nv))
        points = []
        for j, s in enumerate(stance):
            R = foot_R[s]
            for i, loc in enumerate(p.soles[s].local):
                pt = foot_c[s] + R @ (loc - p.sole_offset())
                r = pt - foot_c[s]
                row = 3 * (4 * j + i)
                Jc[row:row + 3] = foot_J[s][:3] - _skew(r) @ foot_J[s][3:]
                points.append(pt)
        points = np.array(points).reshape(-1, 3)

        # ---------------- centroidal tasks on the contact forces
        if k:
            fcols = slice(nv, n)
            sumF = np.tile(np.eye(3), (1, k)) / self.mass
            acc_des = (ref.com_acc + np.array(g.com_kp) * (ref.com_pos - com)
                       + np.array(g.com_kd) * (ref.com_vel - com_vel) + np.array([0, 0, self.gravity]))
            add(sumF, acc_des, g.w_com, fcols)
            moment = np.hstack([_skew(pt - com) for pt in points]) / (self.mass * 0.1)
            add(moment, -g.angmom_kd * L / (self.mass * 0.1), g.w_angmom, fcols)
            add(np.eye(3 * k), np.zeros(3 * k), g.w_reg_f, fcols)

        qcols = slice(0, nv)
        # ---------------- swing feet
        for s in (0, 1):
            if ref.stance[s]:
                continue
            e = ref.foot_pos[s] - foot_c[s]
            ed = ref.foot_vel[s] - foot_J[s][:3] @ qd
            a = ref.foot_acc[s] + g.swing_kp * e + g.swing_kd * ed - foot_Jd[s][:3]
            add(foot_J[s][:3], a, g.w_swing, qcols)
            er = rotation_error(_rot_z(ref.yaw[s]), foot_R[s])
            ar = g.swing_kp * er - g.swing_kd * (foot_J[s][3:] @ qd) - foot_Jd[s][3:]
            add(foot_J[s][3:], ar, g.w_swing_rot, qcols)

        # ---------------- torso and pelvis orientation
        R_yaw = _rot_z(ref.torso_yaw)
        for body, w in ((p.torso_body, g.w_torso), (p.pelvis_body, g.w_pelvis)):
            J, Jd = self._frame_jac(data, body, data.xpos[body])
            er = rotation_error(R_yaw, data.xmat[body].reshape(3, 3))
            a = g.torso_kp * er - g.torso_kd * (J[3:] @ qd) - Jd[3:]
            add(J[3:], a, w, qcols)

        # ---------------- posture
        qj, vj = data.qpos[7:], qd[6:]
        a_post = g.posture_kp * (self.q_posture - qj) - g.posture_kd * vj
        wp = np.where(self.arm, g.w_arm_posture, g.w_posture)
        P[6:nv, 6:nv] += np.diag(wp)
        qv[6:nv] -= wp * a_post
        P[:nv, :nv] += g.w_reg_qdd * np.eye(nv)

        # ---------------- constraints
        JcT = Jc.T
        A_eq = [np.hstack([M[:6], -JcT[:6]])]
        b_eq = [-h[:6]]
        for s in stance:
            v = foot_J[s] @ qd
            A_eq.append(np.hstack([foot_J[s], np.zeros((6, 3 * k))]))
            b_eq.append(-foot_Jd[s] - g.stance_kv * v)
        A = np.vstack(A_eq)
        b = np.concatenate(b_eq)

        lim = p.torque_limit * g.torque_margin
        Sa = p.actuated_dofs
        T = np.hstack([M[Sa], -JcT[Sa]])
        G = [T, -T]
        hh = [lim - h[Sa], lim + h[Sa]]
        lb = np.full(n, -np.inf)
        ub = np.full(n, np.inf)
        if k:
            fr = np.zeros((4 * k + len(stance), n))
            for i in range(k):
                c0 = nv + 3 * i
                fr[4 * i, [c0, c0 + 2]] = (1.0, -g.mu)
                fr[4 * i + 1, [c0, c0 + 2]] = (-1.0, -g.mu)
                fr[4 * i + 2, [c0 + 1, c0 + 2]] = (1.0, -g.mu)
                fr[4 * i + 3, [c0 + 1, c0 + 2]] = (-1.0, -g.mu)
                lb[c0 + 2] = 0.0
            hf = np.zeros(4 * k + len(stance))
            for j, s in enumerate(stance):
                fr[4 * k + j, nv + 12 * j + 2: nv + 12 * j + 12: 3] = 1.0
                hf[4 * k + j] = ref.fz_max[s]
            G.append(fr)
            hh.append(hf)
        G = np.vstack(G)
        hh = np.concatenate(hh)

        x = None
        try:
            x = qpsolvers.solve_qp(P, qv, G, hh, A, b, lb=lb, ub=ub, solver="daqp")
            self.last_solver = "daqp"
        except Exception:  # noqa: BLE001
            x = None
        if x is None:
            try:
                x = qpsolvers.solve_qp(P, qv, G, hh, A, b, lb=lb, ub=ub, solver="quadprog")
                self.last_solver = "quadprog"
            except Exception:  # noqa: BLE001
                x = None
        info = TickInfo(ok=x is not None, solver=self.last_solver)
        if x is None:
            # infeasible: drop the stance and torque constraints' coupling, keep posture (safe fallback)
            tau = np.clip(self.gains.posture_kp * 0.5 * (self.q_posture - qj) - 2.0 * vj + h[Sa], -lim, lim)
            return tau, info
        qdd, f = x[:nv], x[nv:]
        tau = M[Sa] @ qdd + h[Sa] - JcT[Sa] @ f
        forces = np.zeros((2, 3))
        for j, s in enumerate(stance):
            forces[s] = f[12 * j:12 * j + 12].reshape(4, 3).sum(axis=0)
        info.forces = forces
        info.qdd, info.contact_forces, info.contact_jacobian = qdd, f, Jc
        return np.clip(tau, -p.torque_limit, p.torque_limit), info
