"""Whole-body inverse kinematics: from a planned :class:`~gaitshift.trajectory.contract.Trajectory` to q(t), q̇(t).

This is the last block of the planner of paper 001 (§II-A, Fig. 1): "desired joint angles and
velocities are calculated by inverse kinematics for generated CoM, torso, swing leg trajectory".

At each sample k the configuration q_k (MuJoCo qpos: free joint first, then the hinges) solves

    c(q_k)      = p_k                  whole-body CoM (mass-weighted mean of every body), 3 equations
    X_L(q_k)    = (f_L,k, Rz(psi_L,k)) left sole pose (centre, flat, yaw), 6 equations
    X_R(q_k)    = (f_R,k, Rz(psi_R,k)) right sole pose, 6 equations

exactly, and among the solutions keeps the torso upright (yaw = mean sole yaw) and the arms, waist
and legs close to the standing pose (weighted least squares), with the joint limits as inequalities.
Reference motions (:data:`REFERENCE_SETTINGS`, what ``gaitshift export`` of a plan uses) also keep the
pelvis upright at the same yaw, every joint within its soft range (the robot YAML's
``limits.soft_joint_fraction``), leave a swing sole's pitch soft, lay the soles in contact on the
plan's terrain and let the rear sole of a double support pivot about its toe (toe-off)
(:mod:`gaitshift.wholebody.ik_tasks`) only where the plan's ZMP lies in the support that toe-off
leaves; the solved motion is then checked against the plan's physics and its deviation reported
(:mod:`gaitshift.wholebody.plan_fit`). They also keep every joint speed within its limit (the joint
limits of sample k narrowed to q_{k-1} +- v_max dt), hold the heel of a pivoting sole and every corner
of a swing sole above the ground, a swing sole's centre rising above the plan's swing path where its
toe needs it (:mod:`gaitshift.wholebody.ik_ground`), and solve a flight sample whose soles are out of reach again
with the soles' poses soft (only the CoM hard, every sole corner above the ground): in flight no sole
carries a force, so where a sole goes changes neither the CoM's motion nor a contact
(``IKSettings.flight_reach_cost``; the deviation is in the plan-fit report).
Each Newton iteration is one mink QP (daqp through qpsolvers)::

    min_dq  sum_soft ||J_i dq + e_i||^2_{W_i} + damping ||dq||^2
    s.t.    J_h dq = -e_h                  (CoM and both soles, mink ``constraints``)
            q_min <= q + dq <= q_max       (mink ConfigurationLimit)
            G dq <= h                      (sole corners above the ground, reference motions)

The first guess at sample k is the constant-velocity extrapolation q_{k-1} ⊕ (q_{k-1} ⊖ q_{k-2}),
so that one or two iterations usually suffice. q̇ comes from central differences of q on the
configuration manifold (second order in dt).

A plan that the robot cannot follow raises :class:`~gaitshift.errors.InfeasibleError` naming the time
and the failing task (``com``, ``left sole``, ``right sole``, ``joint velocity``) and the cause: foot
out of reach (hip-to-sole distance above the leg length), a joint at its limit, or a knee stretched
into the straight-leg singularity.
"""

from __future__ import annotations

import math
import time
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.common.rotations import rot_y, rot_z
from gaitshift.errors import InputError
from gaitshift.models.terrain import Terrain
from gaitshift.robots.config import RobotConfig, load_robot
from gaitshift.trajectory.contract import Trajectory
from gaitshift.wholebody.ik_diagnosis import IKInfeasibleError, diagnose
from gaitshift.wholebody.ik_diagnosis import check_velocities as check_velocities_of
from gaitshift.wholebody.ik_ground import GroundLimit
from gaitshift.wholebody.ik_settings import REFERENCE_SETTINGS, IKSettings
from gaitshift.wholebody.ik_tasks import (
    SoleTasks,
    SoleTaskSets,
    ToePoint,
    limited_model,
    soft_range,
    sole_angle_error,
    terrain_pitch,
    trailing_soles,
)
from gaitshift.wholebody.joints import JointTrajectory, coordinate_names, joint_velocities, subsample
from gaitshift.wholebody.plan_fit import fit_violation, plan_fit, toe_off_margins

__all__ = ["REFERENCE_SETTINGS", "IKInfeasibleError", "IKSettings", "WholeBodyIK", "wholebody"]


# ====================================================================== IK
class WholeBodyIK:
    """Whole-body IK of one robot (see module docstring). Reusable across trajectories. The robot
    YAML's ``ik`` weights replace those fields of ``settings``."""

    def __init__(self, robot: str | Path | RobotConfig = "g1", settings: IKSettings | None = None):
        import mink
        import mujoco

        self._mujoco, self._mink = mujoco, mink
        self.robot = load_robot(robot)
        weights: dict[str, Any] = dict(self.robot.ik)  # the robot YAML's ik weights (floats)
        self.settings = s = replace(settings or IKSettings(), **weights)
        self.model = m = self.robot.model()
        self.q_stand = self.robot.standing_qpos(m)
        self.conf = mink.Configuration(m, self.q_stand.copy())
        self.sites = [m.site(n).id for n in RobotConfig.SOLE_SITES]
        self.com_task = mink.ComTask(cost=1.0)
        self.sole_tasks = [
            mink.FrameTask(n, "site", position_cost=1.0, orientation_cost=1.0) for n in RobotConfig.SOLE_SITES
        ]
        self.torso_task = mink.FrameTask(self.robot.torso, "body", position_cost=0.0, orientation_cost=s.torso_cost)
        pitch_cost = s.pelvis_cost if s.pelvis_pitch_cost is None else s.pelvis_pitch_cost
        self.pelvis_task = mink.FrameTask(
            self.robot.base, "body", position_cost=0.0, orientation_cost=[s.pelvis_cost, pitch_cost, s.pelvis_cost]
        )
        cost = np.full(m.nv, s.posture_cost)
        cost[:6] = 0.0
        legs = set(self.robot.leg_joints)
        for name in self.robot.joint_names:
            if name not in legs:
                cost[m.jnt_dofadr[m.joint(name).id]] = s.arm_cost
        self.posture_task = mink.PostureTask(m, cost=cost)
        self.posture_task.set_target(self.q_stand)
        jids = [m.joint(n).id for n in self.robot.joint_names]
        rng = self.robot.joint_range
        if s.soft_limits:
            rng = soft_range(rng, self.robot.soft_joint_fraction)
        self.limits = [mink.ConfigurationLimit(limited_model(m, jids, rng) if s.soft_limits else m, gain=0.95)]
        #: rows dropped from the hard constraints: sole roll of legs that cannot roll their foot (5-DOF
        #: legs), and swing sole pitch with ``swing_pitch_cost``
        self.dropped = [
            f"{side} sole roll" for side, ok in zip(("left", "right"), self.robot.foot_roll, strict=True) if not ok
        ] + (["swing sole pitch"] if s.swing_pitch_cost is not None else [])
        self.dropped += ["trailing sole position and pitch (toe point held)"] if s.toe_off_cost is not None else []
        self.dropped += ["swing sole height (soft; its corners above the ground)"] if s.swing_lift_cost else []
        toe = np.array([self.robot.sole_size[0] / 2, 0.0, 0.0])  # the toe edge's middle in the sole frame, m
        self.toe_points = [ToePoint(m, site, toe) for site in self.sites]
        centres = [ToePoint(m, site, np.zeros(3)) for site in self.sites]
        args = (self.robot.foot_roll, s.swing_pitch_cost, self.toe_points, s.toe_off_cost, centres, s.swing_lift_cost)
        self.sole_sets = SoleTaskSets(mink, self.sole_tasks, *args)
        if s.flight_reach_cost is not None:
            self.sole_sets.reaching(mink, s.flight_reach_cost)
        self.soft_base: list[Any] = [self.torso_task, self.posture_task]
        if s.pelvis_cost > 0:
            self.soft_base.append(self.pelvis_task)
        self.knee_adr = [m.joint(n).qposadr[0] for n in self.robot.knees]
        self.hip_ids = [m.joint(n).id for n in self.robot.hips]
        self.qadr = np.array([m.jnt_qposadr[j] for j in jids])
        self.vadr = np.array([m.jnt_dofadr[j] for j in jids])
        #: the joint range the IK keeps to (J, 2), rad: the MJCF's, or its soft range
        self.joint_range = rng
        self.lo, self.hi = rng[:, 0], rng[:, 1]
        self.ground: GroundLimit | None = None
        #: the joint limits' own bounds (nq,), restored before each solve (``speed_limits`` narrows them)
        self.range_bounds = (self.limits[0].lower.copy(), self.limits[0].upper.copy())
        #: samples of the last solve whose flight was solved with soft sole poses (``flight_reach_cost``)
        self.reached: list[int] = []

    # ------------------------------------------------------------------ one sample
    def _errors(self, com: np.ndarray, feet: np.ndarray, rots: list[np.ndarray], tasks: SoleTasks) -> np.ndarray:
        """CoM error (m), sole position errors (m; of the toe point for a pivoting sole) and sole
        orientation errors without their free rows (rad)."""
        d = self.conf.data
        e = np.empty(5)
        e[0] = np.linalg.norm(d.subtree_com[1] - com)
        for i, sid in enumerate(self.sites):
            if tasks.pivot[i]:
                e[1 + i] = np.linalg.norm(self.toe_points[i].point(d) - self.toe_points[i].target)
            elif tasks.lifted[i]:
                e[1 + i] = np.linalg.norm(d.site_xpos[sid, :2] - feet[i, :2])
            else:
                e[1 + i] = np.linalg.norm(d.site_xpos[sid] - feet[i])
            R = d.site_xmat[sid].reshape(3, 3)
            e[3 + i] = sole_angle_error(rots[i], R, tasks.free_roll[i], tasks.free_pitch[i])
        return e

    def _set_targets(self, com: np.ndarray, feet: np.ndarray, yaw: np.ndarray, pitch: np.ndarray) -> list[np.ndarray]:
        """Targets of one sample: CoM ``com`` (3,), soles at ``feet`` (2, 3) m with yaw ``yaw`` (2,) and
        pitch ``pitch`` (2,) rad (toe up, about the world y axis: R = Ry(-pitch) Rz(yaw)); torso and
        pelvis upright at the mean sole yaw. Returns the sole rotations."""
        SE3, SO3 = self._mink.SE3, self._mink.SO3
        self.com_task.set_target(com)
        rots = [rot_y(-float(p)) @ rot_z(float(y)) for y, p in zip(yaw, pitch, strict=True)]
        for task, f, r in zip(self.sole_tasks, feet, rots, strict=True):
            task.set_target(SE3.from_rotation_and_translation(SO3.from_matrix(r), f))
        mid = math.atan2(math.sin(yaw[0]) + math.sin(yaw[1]), math.cos(yaw[0]) + math.cos(yaw[1]))
        upright = SE3.from_rotation_and_translation(SO3.from_matrix(rot_z(mid)), np.zeros(3))
        self.torso_task.set_target(upright)
        self.pelvis_task.set_target(upright)
        self.sole_sets.set_targets()
        return rots

    def _solve_sample(
        self,
        q: np.ndarray,
        com: np.ndarray,
        feet: np.ndarray,
        yaw: np.ndarray,
        contact: np.ndarray,
        max_iter: int,
        pitch: np.ndarray | None = None,
        pivot: np.ndarray | None = None,
        reach: bool = False,
    ) -> tuple[np.ndarray, np.ndarray, int, str | None]:
        """Newton iterations of one sample from ``q`` (nq,): its solution, errors (5,), iterations and
        the solver's failure (or None). ``pitch`` (2,) rad: sole pitch targets (default flat); ``pivot``
        (2,) bool: the soles that may pivot about their toe (default none)."""
        s = self.settings
        rots = self._set_targets(com, feet, yaw, np.zeros(2) if pitch is None else pitch)
        tasks = self.sole_sets.get(contact, (False, False) if pivot is None else pivot, reach)
        limits: list[Any] = list(self.limits)
        if self.ground is not None:
            air = (True, True) if reach else tasks.lifted
            floor = [float(f[2]) if up else None for f, up in zip(feet, tasks.lifted, strict=True)]
            self.ground.hold((False, False) if pivot is None else pivot, air, floor)
            limits = [*self.limits, self.ground]
        hard, soft = [self.com_task, *tasks.hard], self.soft_base + tasks.soft
        conf, damping = self.conf, s.reach_damping if reach else s.damping
        conf.update(q)
        err = self._errors(com, feet, rots, tasks)
        it = 0
        failure = None
        while it < max_iter and not (
            err[0] < s.converged_pos
            and (reach or (max(err[1], err[2]) < s.converged_pos and max(err[3], err[4]) < s.converged_rot))
        ):
            try:
                v = self._mink.solve_ik(conf, soft, 1.0, "daqp", damping=damping, limits=limits, constraints=hard)
            except self._mink.NoSolutionFound:
                failure = "the QP has no solution within the joint limits"
                break
            conf.integrate_inplace(v, 1.0)
            err = self._errors(com, feet, rots, tasks)
            it += 1
        return conf.q.copy(), err, it, failure

    # ------------------------------------------------------------------ whole trajectory
    def solve(self, traj: Trajectory, rate: float | None = None, check_velocities: bool = True) -> JointTrajectory:
        """Joint trajectories reproducing the CoM and sole poses of ``traj`` (sampled at ``rate`` Hz,
        default the plan's own step); ``check_velocities``: raise when a joint exceeds its speed limit.
        On a leg that cannot roll its foot (``RobotConfig.foot_roll``), the sole's roll is dropped from
        the hard constraints (kept as a soft task) and ``meta.ik.dropped_tasks`` says so. With
        ``check_plan_fit``, the motion's deviation from the plan is in ``meta.ik.plan_fit``.

        Raises:
            InfeasibleError: the robot cannot follow the plan (time, task and cause in the message), or
                (``check_plan_fit``) its motion breaks the plan's physics.
            InputError: ``rate`` is not 1/(k dt).
        """
        s = self.settings
        traj = subsample(traj, rate)
        n = len(traj)
        if n < 2:
            raise InputError("trajectory", f"{n} samples", "at least 2 samples")
        pitch = terrain_pitch(traj) if s.terrain_soles else np.zeros((n, 2))
        self.ground = None
        if s.toe_off_cost is not None or s.flight_reach_cost is not None or s.swing_lift_cost is not None:
            terrain = Terrain.from_list(traj.meta.get("terrain"))
            self.ground = GroundLimit(self.model, self.sites, self.robot.sole_size, terrain)
        pivot = trailing_soles(traj.contact) if s.toe_off_cost is not None else np.zeros((n, 2), bool)
        yaw = traj.foot_yaw
        targets = np.array([[rot_y(-float(pitch[k, i])) @ rot_z(float(yaw[k, i])) for i in (0, 1)] for k in range(n)])
        if s.check_plan_fit:
            pivot &= (toe_off_margins(traj, targets, pivot, self.robot.sole_size) >= 0.0)[:, None]
        qpos, errs, iters, sample_time = self._solve_samples(traj, pitch, pivot)
        self.last_sample_times = sample_time
        self.last_iterations = iters
        qvel = joint_velocities(self.model, qpos, traj.dt)
        if check_velocities:
            check_velocities_of(self, traj.t, qvel)
        meta = self._meta(traj, errs, iters, sample_time)
        if s.check_plan_fit:
            reached = np.zeros(n, bool)
            reached[self.reached] = True
            fit = plan_fit(traj, self.model, self.sites, qpos, targets, self.robot.sole_size, s.rot_tol, reached)
            meta["ik"]["plan_fit"] = fit.as_dict()
            broken = fit_violation(fit, s.pos_tol)
            if broken is not None:
                t, task, cause = broken
                raise IKInfeasibleError(
                    f"whole-body IK infeasible for {self.robot.name} at t = {t:.3f} s: task '{task}': {cause}",
                    time=t,
                    task=task,
                    cause=cause,
                )
        return JointTrajectory(traj.t.copy(), qpos, qvel, meta)

    def _solve_samples(
        self, traj: Trajectory, pitch: np.ndarray, pivot: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Every sample of ``traj`` (N) in turn, with sole pitch targets ``pitch`` (N, 2) rad and pivoting
        soles ``pivot`` (N, 2) bool: qpos (N, nq), errors (N, 5), iterations (N,), seconds per sample (N,).

        Raises:
            IKInfeasibleError: the first sample that does not converge within the tolerances.
        """
        s = self.settings
        n = len(traj)
        feet_all, yaw_all, com_all = traj.foot_pos, traj.foot_yaw, traj.com_pos
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
        self.reached = []
        lim = self.limits[0]
        lim.lower[:], lim.upper[:] = self.range_bounds
        step = self.robot.velocity_limit * traj.dt * (1.0 - 1e-6)
        for k in range(n):
            t0 = time.perf_counter()
            lo, hi = self.lo, self.hi
            if k >= 1 and s.speed_limits:
                lo = np.maximum(self.lo, np.minimum(self.hi, qpos[k - 1, self.qadr] - step))
                hi = np.minimum(self.hi, np.maximum(self.lo, qpos[k - 1, self.qadr] + step))
                lim.lower[self.qadr], lim.upper[self.qadr] = lo, hi
            if k >= 2 and s.extrapolate:
                mujoco.mj_integratePos(m, q, v_prev, 1.0)
                q[self.qadr] = np.clip(q[self.qadr], lo, hi)
            iters_k = s.first_iter if k == 0 else s.max_iter
            qk, err, it, failure = self._solve_sample(
                q, com_all[k], feet_all[k], yaw_all[k], traj.contact[k], iters_k, pitch[k], pivot[k]
            )
            bad = self._failed(qk, err, failure)
            if bad and s.flight_reach_cost is not None and not traj.contact[k].any():
                qk, err, it, failure = self._solve_sample(
                    q, com_all[k], feet_all[k], yaw_all[k], traj.contact[k], 4 * iters_k, pitch[k], pivot[k], True
                )
                bad = self._failed(qk, err, failure, reach=True)
                self.reached.append(k)
            if bad:
                raise diagnose(self, float(traj.t[k]), qk, feet_all[k], err, failure)
            qk[self.qadr] = np.clip(qk[self.qadr], lo, hi)  # rounding only (< 1e-15 rad)
            if k >= 1:
                mujoco.mj_differentiatePos(m, v_prev, 1.0, qpos[k - 1], qk)
            qpos[k] = qk
            q = qk.copy()
            errs[k] = err
            iters[k] = it
            sample_time[k] = time.perf_counter() - t0
        return qpos, errs, iters, sample_time

    def _failed(self, qk: np.ndarray, err: np.ndarray, failure: str | None, reach: bool = False) -> bool:
        s = self.settings
        return (
            failure is not None
            or err[0] > s.com_tol
            or (not reach and max(err[1], err[2]) > s.pos_tol)
            or (not reach and max(err[3], err[4]) > s.rot_tol)
            or min(abs(qk[a]) for a in self.knee_adr) < s.knee_margin
        )

    def _meta(self, traj: Trajectory, errs: np.ndarray, iters: np.ndarray, st: np.ndarray) -> dict[str, Any]:
        qpos_names, qvel_names = coordinate_names(self.model)
        return {
            "robot": self.robot.name,
            "mjcf": str(self.robot.mjcf),
            "sole_sites": {
                "left": {"body": self.robot.sole_bodies[0], "pos": list(self.robot.sole_offsets[0])},
                "right": {"body": self.robot.sole_bodies[1], "pos": list(self.robot.sole_offsets[1])},
            },
            "joint_names": list(self.robot.joint_names),
            "qpos_names": qpos_names,
            "qvel_names": qvel_names,
            "dt": traj.dt,
            "scenario": traj.meta.get("scenario"),
            "planner": traj.meta.get("planner"),
            "ik": {
                "max_com_error_m": float(errs[:, 0].max()),
                "max_sole_position_error_m": float(errs[:, 1:3].max()),
                "max_sole_orientation_error_rad": float(errs[:, 3:5].max()),
                "dropped_tasks": list(self.dropped),
                "soft_joint_fraction": self.robot.soft_joint_fraction if self.settings.soft_limits else None,
                "pelvis_cost": self.settings.pelvis_cost,
                "terrain_soles": self.settings.terrain_soles,
                "toe_off_cost": self.settings.toe_off_cost,
                "speed_limits": self.settings.speed_limits,
                "iterations_median": float(np.median(iters)),
                "iterations_max": int(iters.max()),
                "time_per_sample_median_s": float(np.median(st[1:] if len(st) > 1 else st)),
                "time_per_sample_p99_s": float(np.percentile(st[1:] if len(st) > 1 else st, 99)),
                "total_time_s": float(st.sum()),
            },
        }


def wholebody(
    traj: Trajectory | str | Path,
    robot: str | Path | RobotConfig = "g1",
    rate: float | None = None,
    settings: IKSettings | None = None,
) -> JointTrajectory:
    """Joint trajectories of ``robot`` following the plan ``traj`` (a Trajectory or its file)."""
    if not isinstance(traj, Trajectory):
        traj = Trajectory.load(traj)
    return WholeBodyIK(robot, settings).solve(traj, rate)
