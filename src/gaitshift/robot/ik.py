"""Whole-body inverse kinematics: from a planned :class:`~gaitshift.trajectory.Trajectory` to q(t), q̇(t).

This is the last block of the planner of paper 001 (§II-A, Fig. 1): "desired joint angles and
velocities are calculated by inverse kinematics for generated CoM, torso, swing leg trajectory".

At each sample k the configuration q_k (MuJoCo qpos: free joint first, then the hinges) solves

    c(q_k)      = p_k                  whole-body CoM (mass-weighted mean of every body), 3 equations
    X_L(q_k)    = (f_L,k, Rz(psi_L,k)) left sole pose (centre, flat, yaw), 6 equations
    X_R(q_k)    = (f_R,k, Rz(psi_R,k)) right sole pose, 6 equations

exactly, and among the solutions keeps the torso upright (yaw = mean sole yaw) and the arms, waist
and legs close to the standing pose (weighted least squares), with the joint limits as inequalities.
Each Newton iteration is one mink QP (daqp through qpsolvers)::

    min_dq  sum_soft ||J_i dq + e_i||^2_{W_i} + damping ||dq||^2
    s.t.    J_h dq = -e_h                  (CoM and both soles, mink ``constraints``)
            q_min <= q + dq <= q_max       (mink ConfigurationLimit)

The first guess at sample k is the constant-velocity extrapolation q_{k-1} ⊕ (q_{k-1} ⊖ q_{k-2}),
so that one or two iterations usually suffice. q̇ comes from central differences of q on the
configuration manifold (second order in dt).

A plan that the robot cannot follow raises :class:`~gaitshift.errors.InfeasibleError` naming the time
and the failing task (``com``, ``left sole``, ``right sole``, ``joint velocity``) and the cause: foot
out of reach (hip-to-sole distance above the leg length), a joint at its limit, or a knee stretched
into the straight-leg singularity.
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InfeasibleError, InputError
from ..io import atomic_path
from ..swing import min_jerk
from ..trajectory import Trajectory
from .config import RobotConfig, load_robot

TASKS = ("com", "left sole", "right sole")


class IKInfeasibleError(InfeasibleError):
    """The robot cannot follow the plan. Attributes: ``time`` (s), ``task`` (one of ``com``,
    ``left sole``, ``right sole``, ``joint velocity``) and ``cause`` (text)."""

    def __init__(self, message: str, *, time: float, task: str, cause: str):
        super().__init__(message)
        self.time = time
        self.task = task
        self.cause = cause


@dataclass(frozen=True)
class IKSettings:
    """Tolerances and weights of the whole-body IK.

    Attributes:
        com_tol, pos_tol, rot_tol: a sample whose CoM error (m), sole position error (m) or sole
            orientation error (rad) stays above these after ``max_iter`` iterations is infeasible.
        converged_pos, converged_rot: stop iterating below these errors (m, rad).
        max_iter: Newton iterations per sample; ``first_iter`` for the first sample (from standing).
        knee_margin: a knee within this angle (rad) of straight is a singularity.
        torso_cost, posture_cost, arm_cost: weights of the soft tasks (unitless, per rad).
        damping: Levenberg-Marquardt damping of the QP.
        extrapolate: warm-start each sample at q_{k-1} ⊕ (q_{k-1} ⊖ q_{k-2}) (else at q_{k-1}).
    """

    com_tol: float = 1e-3
    pos_tol: float = 5e-4
    rot_tol: float = 5e-3
    converged_pos: float = 2e-5
    converged_rot: float = 2e-4
    max_iter: int = 12
    first_iter: int = 200
    knee_margin: float = 0.05
    torso_cost: float = 1.0
    posture_cost: float = 0.02
    arm_cost: float = 0.5
    damping: float = 1e-6
    extrapolate: bool = True


@dataclass(frozen=True)
class JointTrajectory:
    """Joint trajectories of a robot.

    Attributes:
        t: (N,) time, s.
        qpos: (N, nq) MuJoCo generalized positions (free joint: x, y, z, qw, qx, qy, qz first).
        qvel: (N, nv) MuJoCo generalized velocities (free joint: world linear, body angular first).
        meta: JSON-able dict: robot, mjcf, joint_names, qpos_names, qvel_names, ik errors, source.
    """

    t: np.ndarray
    qpos: np.ndarray
    qvel: np.ndarray
    meta: dict[str, Any] = field(default_factory=dict)

    def save(self, path: str | Path) -> Path:
        """Write ``t``, ``qpos``, ``qvel`` and ``meta`` (JSON string) to an ``.npz``, atomically."""
        path = Path(path)
        if path.suffix.lower() != ".npz":
            raise InputError("out", str(path), "a file ending in .npz")
        with atomic_path(path) as tmp:
            np.savez_compressed(tmp, t=self.t, qpos=self.qpos, qvel=self.qvel,
                                meta=np.array(json.dumps(self.meta)))
        return path

    @classmethod
    def load(cls, path: str | Path) -> "JointTrajectory":
        path = Path(path)
        if not path.is_file():
            raise InputError("file", str(path), "an existing joints .npz file")
        with np.load(path, allow_pickle=False) as z:
            missing = [k for k in ("t", "qpos", "qvel", "meta") if k not in z.files]
            if missing:
                raise InputError("file", str(path), f"a joints file with keys t, qpos, qvel, meta (missing {missing})")
            return cls(z["t"], z["qpos"], z["qvel"], json.loads(str(z["meta"])))


# ====================================================================== targets
def sole_yaw(traj: Trajectory) -> np.ndarray:
    """Yaw of each sole, (N, 2) rad.

    ``extras['foot_yaw']`` if the planner gave it; otherwise each contact interval takes the yaw of
    the footstep (same side) nearest to the sole, and each swing blends the yaws of the contacts
    around it with the minimum-jerk profile of :mod:`gaitshift.swing` (the same blend as the swing
    position).
    """
    n = len(traj)
    if "foot_yaw" in traj.extras and np.shape(traj.extras["foot_yaw"]) == (n, 2):
        return np.asarray(traj.extras["foot_yaw"], float)
    out = np.zeros((n, 2))
    for side in (0, 1):
        steps = traj.footsteps[traj.footstep_side == side]
        if len(steps) == 0:
            continue
        c = traj.contact[:, side].astype(np.int8)
        edges = np.flatnonzero(np.diff(c)) + 1
        bounds = np.concatenate([[0], edges, [n]])
        yaws, kinds = [], []
        for a, b in zip(bounds[:-1], bounds[1:]):
            if c[a]:
                d = np.linalg.norm(steps[:, :2] - traj.foot_pos[a, side, :2], axis=1)
                yaws.append(float(steps[np.argmin(d), 3]))
            else:
                yaws.append(math.nan)
            kinds.append(c[a])
        known = [y for y in yaws if not math.isnan(y)]
        default = known[0] if known else 0.0
        for i, (a, b) in enumerate(zip(bounds[:-1], bounds[1:])):
            if kinds[i]:
                out[a:b, side] = yaws[i]
                continue
            before = next((yaws[j] for j in range(i - 1, -1, -1) if kinds[j]), None)
            after = next((yaws[j] for j in range(i + 1, len(yaws)) if kinds[j]), None)
            y0 = before if before is not None else (after if after is not None else default)
            y1 = after if after is not None else y0
            y1 = y0 + (y1 - y0 + math.pi) % (2 * math.pi) - math.pi
            u = (np.arange(a, b) - a + 1) / (b - a + 1)
            out[a:b, side] = y0 + (y1 - y0) * min_jerk(u)
    return out


def subsample(traj: Trajectory, rate: float | None) -> Trajectory:
    """Every k-th sample of ``traj`` so that the step is 1/``rate`` (k integer), or ``traj`` itself."""
    if rate is None or len(traj) < 2:
        return traj
    if not (rate > 0 and math.isfinite(rate)):
        raise InputError("rate", rate, "a positive sampling rate, Hz")
    k = 1.0 / (rate * traj.dt)
    step = int(round(k))
    if step < 1 or abs(k - step) > 1e-6 * k:
        raise InputError("rate", rate, f"1/(k dt) for an integer k >= 1 (plan step dt = {traj.dt:g} s)")
    if step == 1:
        return traj
    arrays = {key: v[::step] if np.ndim(v) and len(v) == len(traj) else v for key, v in traj.arrays().items()}
    arrays["footsteps"], arrays["footstep_side"] = traj.footsteps, traj.footstep_side
    return Trajectory.from_arrays(arrays, dict(traj.meta))


# ====================================================================== manifold helpers
def _quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    aw, ax, ay, az = np.moveaxis(a, -1, 0)
    bw, bx, by, bz = np.moveaxis(b, -1, 0)
    return np.stack([aw * bw - ax * bx - ay * by - az * bz,
                     aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw], axis=-1)


def _quat_log(q: np.ndarray) -> np.ndarray:
    """Rotation vector (..., 3) of unit quaternions (..., 4) (w first), shortest path."""
    q = np.where(q[..., :1] < 0, -q, q)
    v = q[..., 1:]
    s = np.linalg.norm(v, axis=-1)
    angle = 2.0 * np.arctan2(s, q[..., 0])
    scale = np.where(s > 1e-12, angle / np.maximum(s, 1e-300), 2.0)
    return v * scale[..., None]


def qpos_difference(model: Any, q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """q1 ⊖ q0 for arrays of configurations (..., nq) -> (..., nv), like ``mj_differentiatePos``
    with dt = 1: free-joint linear part in the world frame, angular part in the body frame
    (log of conj(quat0) * quat1); hinges and slides subtract."""
    out = np.empty(q0.shape[:-1] + (model.nv,))
    out[..., 0:3] = q1[..., 0:3] - q0[..., 0:3]
    conj = q0[..., 3:7] * np.array([1.0, -1.0, -1.0, -1.0])
    out[..., 3:6] = _quat_log(_quat_mul(conj, q1[..., 3:7]))
    out[..., 6:] = q1[..., 7:] - q0[..., 7:]
    return out


def joint_velocities(model: Any, qpos: np.ndarray, dt: float) -> np.ndarray:
    """q̇ (N, nv) from q (N, nq): central differences inside, one-sided at both ends."""
    n = len(qpos)
    qvel = np.zeros((n, model.nv))
    if n < 2:
        return qvel
    qvel[1:-1] = qpos_difference(model, qpos[:-2], qpos[2:]) / (2 * dt)
    qvel[0] = qpos_difference(model, qpos[0], qpos[1]) / dt
    qvel[-1] = qpos_difference(model, qpos[-2], qpos[-1]) / dt
    return qvel


def _rotz(yaw: float) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _rot_angle(r_target: np.ndarray, r: np.ndarray) -> float:
    c = (np.trace(r_target.T @ r) - 1.0) / 2.0
    return float(math.acos(min(1.0, max(-1.0, c))))


# ====================================================================== IK
class WholeBodyIK:
    """Whole-body IK of one robot (see module docstring). Reusable across trajectories."""

    def __init__(self, robot: "str | Path | RobotConfig" = "g1", settings: IKSettings | None = None):
        import mink
        import mujoco

        self._mujoco, self._mink = mujoco, mink
        self.robot = load_robot(robot)
        self.settings = s = settings or IKSettings()
        self.model = m = self.robot.model()
        self.q_stand = self.robot.standing_qpos(m)
        self.conf = mink.Configuration(m, self.q_stand.copy())
        self.sites = [m.site(n).id for n in RobotConfig.SOLE_SITES]
        self.com_task = mink.ComTask(cost=1.0)
        self.sole_tasks = [mink.FrameTask(n, "site", position_cost=1.0, orientation_cost=1.0)
                           for n in RobotConfig.SOLE_SITES]
        self.torso_task = mink.FrameTask(self.robot.torso, "body", position_cost=0.0,
                                         orientation_cost=s.torso_cost)
        cost = np.full(m.nv, s.posture_cost)
        cost[:6] = 0.0
        legs = set(self.robot.leg_joints)
        for name in self.robot.joint_names:
            if name not in legs:
                cost[m.jnt_dofadr[m.joint(name).id]] = s.arm_cost
        self.posture_task = mink.PostureTask(m, cost=cost)
        self.posture_task.set_target(self.q_stand)
        self.limits = [mink.ConfigurationLimit(m, gain=0.95)]
        self.hard = [self.com_task, *self.sole_tasks]
        self.soft = [self.torso_task, self.posture_task]
        self.knee_adr = [m.joint(n).qposadr[0] for n in self.robot.knees]
        self.hip_ids = [m.joint(n).id for n in self.robot.hips]
        jids = [m.joint(n).id for n in self.robot.joint_names]
        self._qadr = np.array([m.jnt_qposadr[j] for j in jids])
        self._vadr = np.array([m.jnt_dofadr[j] for j in jids])
        self._lo, self._hi = self.robot.joint_range[:, 0], self.robot.joint_range[:, 1]

    # ------------------------------------------------------------------ one sample
    def _errors(self, com: np.ndarray, feet: np.ndarray, rots: list[np.ndarray]) -> np.ndarray:
        d = self.conf.data
        e = np.empty(5)
        e[0] = np.linalg.norm(d.subtree_com[1] - com)
        for i, sid in enumerate(self.sites):
            e[1 + i] = np.linalg.norm(d.site_xpos[sid] - feet[i])
            e[3 + i] = _rot_angle(rots[i], d.site_xmat[sid].reshape(3, 3))
        return e

    def _set_targets(self, com: np.ndarray, feet: np.ndarray, yaw: np.ndarray) -> list[np.ndarray]:
        SE3, SO3 = self._mink.SE3, self._mink.SO3
        self.com_task.set_target(com)
        rots = [_rotz(float(y)) for y in yaw]
        for task, f, r in zip(self.sole_tasks, feet, rots):
            task.set_target(SE3.from_rotation_and_translation(SO3.from_matrix(r), f))
        mid = math.atan2(math.sin(yaw[0]) + math.sin(yaw[1]), math.cos(yaw[0]) + math.cos(yaw[1]))
        self.torso_task.set_target(SE3.from_rotation_and_translation(SO3.from_matrix(_rotz(mid)), np.zeros(3)))
        return rots

    def _solve_sample(self, q: np.ndarray, com: np.ndarray, feet: np.ndarray, yaw: np.ndarray,
                      max_iter: int) -> tuple[np.ndarray, np.ndarray, int, str | None]:
        s = self.settings
        rots = self._set_targets(com, feet, yaw)
        conf = self.conf
        conf.update(q)
        err = self._errors(com, feet, rots)
        it = 0
        failure = None
        while it < max_iter and not (err[0] < s.converged_pos and max(err[1], err[2]) < s.converged_pos
                                     and max(err[3], err[4]) < s.converged_rot):
            try:
                v = self._mink.solve_ik(conf, self.soft, 1.0, "daqp", damping=s.damping,
                                        limits=self.limits, constraints=self.hard)
            except self._mink.NoSolutionFound:
                failure = "the QP has no solution within the joint limits"
                break
            conf.integrate_inplace(v, 1.0)
            err = self._errors(com, feet, rots)
            it += 1
        return conf.q.copy(), err, it, failure

    # ------------------------------------------------------------------ diagnosis
    def _diagnose(self, t: float, q: np.ndarray, feet: np.ndarray, err: np.ndarray, failure: str | None) -> IKInfeasibleError:
        s = self.settings
        d = self.conf.data
        self.conf.update(q)
        ratios = np.array([err[0] / s.com_tol, max(err[1] / s.pos_tol, err[3] / s.rot_tol),
                           max(err[2] / s.pos_tol, err[4] / s.rot_tol)])
        task = int(np.argmax(ratios))
        causes = []
        reach = [float(np.linalg.norm(feet[i] - d.xanchor[self.hip_ids[i]])) for i in (0, 1)]
        leg = self.robot.leg_length
        sides = ("left", "right")
        for side in (0, 1):
            if reach[side] > leg:
                causes.append((side + 1, f"{sides[side]} foot out of reach (hip-to-sole distance "
                               f"{reach[side]:.3f} m > leg length {leg:.3f} m)"))
        lo, hi = self.robot.joint_range[:, 0], self.robot.joint_range[:, 1]
        qj = q[self._qadr]
        for j in np.flatnonzero((qj - lo < 1e-2) | (hi - qj < 1e-2)):
            name = self.robot.joint_names[j]
            causes.append((None, f"joint limit ({name} = {qj[j]:.3f} rad, range [{lo[j]:.3f}, {hi[j]:.3f}])"))
        for side, adr in enumerate(self.knee_adr):
            if abs(q[adr]) < s.knee_margin:
                causes.append((side + 1, f"knee singularity ({self.robot.knees[side]} = {q[adr]:.3f} rad, leg "
                               f"straight; {sides[side]} hip-to-sole distance {reach[side]:.3f} m, leg length "
                               f"{leg:.3f} m)"))
        if causes and causes[0][0] is not None and (ratios[causes[0][0]] > 1 or ratios.max() <= 1):
            task = causes[0][0]
        if not causes:
            side = task - 1 if task else int(np.argmax(reach))
            causes.append((None, f"{failure or 'no converged solution'} ({sides[side]} hip-to-sole distance "
                           f"{reach[side]:.3f} m, leg length {leg:.3f} m)"))
        cause = "; ".join(c for _, c in causes)
        miss = err[0] if task == 0 else max(err[task], 0.0)
        rot = err[2 + task] if task else 0.0
        return IKInfeasibleError(
            f"whole-body IK infeasible for {self.robot.name} at t = {t:.3f} s: task '{TASKS[task]}' misses "
            f"its target by {miss * 1e3:.1f} mm" + (f" / {rot:.3f} rad" if task else "") + f": {cause}",
            time=t, task=TASKS[task], cause=cause)

    # ------------------------------------------------------------------ whole trajectory
    def solve(self, traj: Trajectory, rate: float | None = None) -> JointTrajectory:
        """Joint trajectories reproducing the CoM and sole poses of ``traj`` (sampled at ``rate`` Hz,
        default the plan's own step).

        Raises:
            InfeasibleError: the robot cannot follow the plan (time, task and cause in the message).
            InputError: ``rate`` is not 1/(k dt).
        """
        s = self.settings
        traj = subsample(traj, rate)
        n = len(traj)
        if n < 2:
            raise InputError("trajectory", f"{n} samples", "at least 2 samples")
        dt = traj.dt
        feet_all = traj.foot_pos
        yaw_all = sole_yaw(traj)
        com_all = traj.com_pos
        m = self.model
        mujoco = self._mujoco

        # start: standing pose moved so that its soles sit on the first targets
        q = self.q_stand.copy()
        d = self.conf.data
        self.conf.update(q)
        q[0:3] += feet_all[0].mean(axis=0) - d.site_xpos[self.sites].mean(axis=0)
        q[3:7] = (math.cos(yaw_all[0].mean() / 2), 0.0, 0.0, math.sin(yaw_all[0].mean() / 2))
        qpos = np.empty((n, m.nq))
        errs = np.empty((n, 5))
        iters = np.empty(n, dtype=np.int32)
        sample_time = np.empty(n)
        v_prev = np.zeros(m.nv)
        for k in range(n):
            t0 = time.perf_counter()
            if k >= 2 and s.extrapolate:
                mujoco.mj_integratePos(m, q, v_prev, 1.0)
                q[self._qadr] = np.clip(q[self._qadr], self._lo, self._hi)
            qk, err, it, failure = self._solve_sample(q, com_all[k], feet_all[k], yaw_all[k],
                                                      s.first_iter if k == 0 else s.max_iter)
            if (failure is not None or err[0] > s.com_tol or max(err[1], err[2]) > s.pos_tol
                    or max(err[3], err[4]) > s.rot_tol
                    or min(abs(qk[a]) for a in self.knee_adr) < s.knee_margin):
                raise self._diagnose(float(traj.t[k]), qk, feet_all[k], err, failure)
            qk[self._qadr] = np.clip(qk[self._qadr], self._lo, self._hi)  # rounding only (< 1e-15 rad)
            if k >= 1:
                mujoco.mj_differentiatePos(m, v_prev, 1.0, qpos[k - 1], qk)
            qpos[k] = qk
            q = qk.copy()
            errs[k] = err
            iters[k] = it
            sample_time[k] = time.perf_counter() - t0
        self.last_sample_times = sample_time
        self.last_iterations = iters
        qvel = joint_velocities(m, qpos, dt)
        self._check_velocities(traj.t, qvel)
        return JointTrajectory(traj.t.copy(), qpos, qvel, self._meta(traj, errs, iters, sample_time))

    def _check_velocities(self, t: np.ndarray, qvel: np.ndarray) -> None:
        vj = np.abs(qvel[:, self._vadr])
        if not np.all(np.isfinite(vj)):
            k = int(np.argmax(~np.all(np.isfinite(vj), axis=1)))
            raise IKInfeasibleError(f"whole-body IK infeasible for {self.robot.name} at t = {t[k]:.3f} s: "
                                  "task 'joint velocity' is not finite", time=float(t[k]),
                                  task="joint velocity", cause="non-finite velocity")
        over = vj / self.robot.velocity_limit
        if np.any(over > 1.0):
            k, j = np.unravel_index(int(np.argmax(over)), over.shape)
            name = self.robot.joint_names[j]
            cause = f"{name} at {vj[k, j]:.2f} rad/s > limit {self.robot.velocity_limit[j]:.2f} rad/s"
            raise IKInfeasibleError(f"whole-body IK infeasible for {self.robot.name} at t = {t[k]:.3f} s: task "
                                  f"'joint velocity' exceeds the velocity limit: {cause}", time=float(t[k]),
                                  task="joint velocity", cause=cause)

    def _meta(self, traj: Trajectory, errs: np.ndarray, iters: np.ndarray, st: np.ndarray) -> dict[str, Any]:
        m = self.model
        qpos_names, qvel_names = [], []
        for j in range(m.njnt):
            name = m.joint(j).name or "root"
            if int(m.jnt_type[j]) == int(self._mujoco.mjtJoint.mjJNT_FREE):
                qpos_names += [f"{name}:{c}" for c in ("x", "y", "z", "qw", "qx", "qy", "qz")]
                qvel_names += [f"{name}:{c}" for c in ("vx", "vy", "vz", "wx", "wy", "wz")]
            else:
                qpos_names.append(name)
                qvel_names.append(name)
        return {
            "robot": self.robot.name,
            "mjcf": str(self.robot.mjcf),
            "sole_sites": {"left": {"body": self.robot.sole_bodies[0], "pos": list(self.robot.sole_offsets[0])},
                           "right": {"body": self.robot.sole_bodies[1], "pos": list(self.robot.sole_offsets[1])}},
            "joint_names": list(self.robot.joint_names),
            "qpos_names": qpos_names,
            "qvel_names": qvel_names,
            "dt": traj.dt,
            "scenario": traj.meta.get("scenario"),
            "planner": traj.meta.get("planner"),
            "ik": {"max_com_error_m": float(errs[:, 0].max()),
                   "max_sole_position_error_m": float(errs[:, 1:3].max()),
                   "max_sole_orientation_error_rad": float(errs[:, 3:5].max()),
                   "iterations_median": float(np.median(iters)), "iterations_max": int(iters.max()),
                   "time_per_sample_median_s": float(np.median(st[1:] if len(st) > 1 else st)),
                   "time_per_sample_p99_s": float(np.percentile(st[1:] if len(st) > 1 else st, 99)),
                   "total_time_s": float(st.sum())},
        }


def wholebody(traj: Trajectory | str | Path, robot: "str | Path | RobotConfig" = "g1",
              rate: float | None = None, settings: IKSettings | None = None) -> JointTrajectory:
    """Joint trajectories of ``robot`` following the plan ``traj`` (a Trajectory or its file)."""
    if not isinstance(traj, Trajectory):
        traj = Trajectory.load(traj)
    return WholeBodyIK(robot, settings).solve(traj, rate)


def load_plan(source: "Trajectory | str | Path") -> Trajectory:
    """A plan from a trajectory file (.npz/.csv/.json), or planned from a scenario (built-in name or
    .yaml path)."""
    if isinstance(source, Trajectory):
        return source
    path = Path(str(source))
    if path.suffix.lower() in (".npz", ".csv", ".json"):
        return Trajectory.load(path)
    from .. import plan
    from ..scenario import load_scenario

    return plan(load_scenario(str(source)))
