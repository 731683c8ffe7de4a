"""The sole tasks of the whole-body IK (:mod:`gaitshift.wholebody.ik`) per contact state, the orientation
errors they are judged by, and the soft joint range the IK may keep to.

A sole's pose target is the six rows of a mink ``FrameTask`` error (a twist in the sole frame): position
x, y, z (m), then the rotation about the sole's x (roll), y (pitch) and z (yaw) axes (rad). The rows are
equality constraints of the IK's QP, except:

* roll (row 3) of a leg that cannot roll its foot (5-DOF legs, ``RobotConfig.foot_roll``): dropped at
  every sample and kept as a soft task of weight 1 on the whole sole pose;
* pitch (row 4) of a swing sole (not in contact in the plan's ``contact``) when a swing pitch weight is
  given (``IKSettings.swing_pitch_cost``): dropped, and kept as a soft task of that weight pulling the
  sole flat. The plan gives a swing foot's position and yaw; its pitch in the air changes neither the
  CoM's dynamics nor a contact, and a flat swing sole behind the body is what drives the ankle pitch to
  its limit at lift-off;
* the trailing sole of a double support (the foot that lifts off next, :func:`trailing_soles`) when a
  toe-off weight is given (``IKSettings.toe_off_cost``): it may pivot about its toe edge, heel up, as a
  walker's rear foot does before lift-off. Its position rows are replaced by the toe point (the sole's
  front edge, ``RobotConfig.sole_size[0] / 2`` ahead of the sole centre, :class:`ToePoint`) held at its
  planned place, roll and yaw stay hard, and the pitch becomes a soft task of that weight pulling the
  sole flat on the ground (it only lifts where the ankle's range leaves no other solution). Whether the
  plan's ZMP stays within the smaller support this leaves is checked by :mod:`gaitshift.wholebody.plan_fit`.

* a swing sole's height when a lift weight is given (``IKSettings.swing_lift_cost``): its position rows
  are replaced by its centre's horizontal position in the world (hard; :class:`ToePoint` with no offset)
  and its height, a soft task of that weight (:class:`PointCost`) with the centre held on or above its
  planned height and every corner of the sole on or above the ground (:mod:`gaitshift.wholebody.ik_ground`).
  A sole pitched toe down just after lift-off (its ankle at its soft limit) would otherwise go through
  the ground where the plan's swing path starts on it: its centre rises by what its toe needs. In a
  flight solved with soft soles (:meth:`SoleTaskSets.reaching`) the height keeps that weight.

Any other sole in contact lies on the ground (all its rows hard): flat, or, with
``IKSettings.terrain_soles``, inclined as the plan's terrain under its foothold (:func:`terrain_pitch`).

The soft range of a joint (mjlab's ``soft_joint_pos_limits``): centre +- f x half range, f =
``RobotConfig.soft_joint_fraction`` (robot YAML ``limits.soft_joint_fraction``, 0.9 by default).
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from gaitshift.gait.swing import foot_yaws
from gaitshift.models.terrain import Terrain
from gaitshift.trajectory.contract import Trajectory

#: rows of a sole task: position x, y, z, rotation about the sole's x (roll), y (pitch), z (yaw)
ROLL, PITCH = 3, 4
#: mink's error-scaled Levenberg-Marquardt damping of the soft sole tasks of a flight out of reach
#: (``FrameTask(lm_damping=...)``): without it, g1-top-speed's trailing sole (knee straight) takes
#: Newton steps of 0.3-0.5 rad that leave the CoM 5 mm off after 48 iterations (t = 3.65 s)
REACH_LM_DAMPING = 1.0


class RowsTask:
    """Some rows of a mink task's error and Jacobian, as an equality constraint (mink reads ``gain``,
    ``compute_error`` and ``compute_jacobian`` of its constraints)."""

    def __init__(self, task: Any, rows: tuple[int, ...]):
        self.task, self.rows, self.gain = task, list(rows), task.gain

    def compute_error(self, configuration: Any) -> np.ndarray:
        return np.asarray(self.task.compute_error(configuration))[self.rows]

    def compute_jacobian(self, configuration: Any) -> np.ndarray:
        return np.asarray(self.task.compute_jacobian(configuration))[self.rows]


def _angle(c: float) -> float:
    return float(math.acos(min(1.0, max(-1.0, c))))


def sole_angle_error(r_target: np.ndarray, r: np.ndarray, free_roll: bool, free_pitch: bool) -> float:
    """Orientation error (rad) of a sole frame ``r`` (3, 3) against ``r_target`` (3, 3), leaving out the
    free rotations: the full angle; without roll, the angle between the x axes; without pitch, between
    the y axes; without both, between the horizontal projections of the x axes (the yaw error)."""
    if not free_roll and not free_pitch:
        return _angle((np.trace(r_target.T @ r) - 1.0) / 2.0)
    if free_roll and free_pitch:
        a = math.atan2(r[1, 0], r[0, 0]) - math.atan2(r_target[1, 0], r_target[0, 0])
        return abs(math.remainder(a, math.tau))
    axis = 0 if free_roll else 1
    return _angle(float(r_target[:, axis] @ r[:, axis]))


def soft_range(joint_range: np.ndarray, fraction: float) -> np.ndarray:
    """The middle ``fraction`` of each range of ``joint_range`` (J, 2), rad: centre +- fraction x half
    range; an unlimited joint (+-inf) stays unlimited. Returns (J, 2)."""
    rng = np.array(joint_range, dtype=float)
    finite = np.all(np.isfinite(rng), axis=1)
    mid = rng[finite].mean(axis=1)
    half = (rng[finite, 1] - rng[finite, 0]) / 2.0
    rng[finite] = np.stack([mid - fraction * half, mid + fraction * half], axis=1)
    return rng


def limited_model(model: Any, joint_ids: list[int], joint_range: np.ndarray) -> Any:
    """A copy of the MuJoCo ``model`` whose joints ``joint_ids`` have the limits ``joint_range`` (J, 2)
    (unlimited ones left as they are): the model of the IK's ``ConfigurationLimit``."""
    out = copy.copy(model)
    for j, (lo, hi) in zip(joint_ids, joint_range, strict=True):
        if math.isfinite(lo) and math.isfinite(hi):
            out.jnt_range[j] = (lo, hi)
    return out


def terrain_pitch(traj: Trajectory) -> np.ndarray:
    """Inclination of each sole (N, 2) rad, positive toe up: in contact the pitch of the plan's terrain
    (``meta["terrain"]``, :class:`~gaitshift.models.terrain.Terrain`) under its foothold, atan(dz/dx); in
    a swing the minimum-jerk blend from the lift-off foothold's to the touchdown foothold's
    (:func:`gaitshift.gait.swing.foot_yaws`, as the yaws); zeros on flat ground. The same pitch as the
    closed loop's sole references (``PlanSamples.foot_pitch``)."""
    terrain = Terrain.from_list(traj.meta.get("terrain"))
    if terrain.flat:
        return np.zeros((len(traj), 2))
    steps = traj.footsteps.copy()
    steps[:, 3] = np.arctan(terrain.slope(steps[:, 0]))  # each foothold's pitch in the yaw column
    return foot_yaws(traj.contact.astype(bool), traj.foot_pos, steps, traj.footstep_side)


def trailing_soles(contact: np.ndarray) -> np.ndarray:
    """(N, 2) bool: the sole of each double support (``contact`` (N, 2) both true) whose next lift-off
    comes first (strictly), i.e. the rear foot about to swing; false elsewhere (a single support's stance
    sole carries the whole ZMP and never pivots)."""
    c = np.asarray(contact, bool)
    n = len(c)
    nxt = np.empty((n, 2), dtype=np.int64)
    for side in (0, 1):
        lift = np.append(np.flatnonzero(c[:-1, side] & ~c[1:, side]) + 1, n)  # first samples off the ground, n
        nxt[:, side] = lift[np.searchsorted(lift, np.arange(n), side="right")]
    ds = c[:, 0] & c[:, 1]
    return np.stack([ds & (nxt[:, 0] < nxt[:, 1]), ds & (nxt[:, 1] < nxt[:, 0])], axis=1)


class ToePoint:
    """The toe point of a sole as an equality constraint of the IK: the point ``offset`` (3,) m of the sole
    site's frame (``[sole length / 2, 0, 0]``: the middle of its front edge), error p(q) - target (3,) m in
    the world frame, Jacobian (3, nv) from ``mj_jac`` on the sole's body."""

    def __init__(self, model: Any, site: int, offset: np.ndarray):
        import mujoco

        self._mj_jac = mujoco.mj_jac
        self.site, self.body, self.offset = site, int(model.site_bodyid[site]), np.asarray(offset, float)
        self.target, self.gain = np.zeros(3), 1.0
        self._jacp, self._jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))

    def point(self, data: Any) -> np.ndarray:
        """The toe point in the world (3,), m."""
        return np.asarray(data.site_xpos[self.site] + data.site_xmat[self.site].reshape(3, 3) @ self.offset)

    def set_target(self, centre: np.ndarray, rotation: np.ndarray) -> None:
        """Target: the toe point of a sole at ``centre`` (3,) m with the orientation ``rotation`` (3, 3)."""
        self.target = np.asarray(centre, float) + rotation @ self.offset

    def compute_error(self, configuration: Any) -> np.ndarray:
        return self.point(configuration.data) - self.target

    def compute_jacobian(self, configuration: Any) -> np.ndarray:
        d = configuration.data
        self._mj_jac(configuration.model, d, self._jacp, self._jacr, self.point(d), self.body)
        return self._jacp.copy()


class PointCost:
    """A soft task of the IK: a sole point (:class:`ToePoint`) at its target, weights ``cost`` (3,) per m
    along the world's x, y, z, with mink's error-scaled Levenberg-Marquardt damping ``lm_damping`` (mink
    reads ``compute_qp_residual`` of a soft task: weighted Jacobian, weighted error, damping)."""

    def __init__(self, point: ToePoint, cost: Any, lm_damping: float = 0.0):
        self.point, self.cost, self.lm_damping = point, np.asarray(cost, float), lm_damping
        self.rows = np.flatnonzero(self.cost)

    def compute_qp_residual(self, configuration: Any) -> tuple[np.ndarray, np.ndarray, float]:
        w = self.cost[self.rows]
        e = -w * self.point.compute_error(configuration)[self.rows]
        return w[:, None] * self.point.compute_jacobian(configuration)[self.rows], e, self.lm_damping * float(e @ e)


@dataclass(frozen=True)
class SoleTasks:
    """The sole tasks of one contact state: ``hard`` (equality constraints), ``soft`` (weighted tasks) and,
    per side (left, right), whether roll and pitch are free (left out of the orientation error) and
    whether the sole is held by its toe point (``pivot``: its position error is then the toe point's) or
    by its centre's horizontal position with a soft height (``lifted``: its position error is horizontal)."""

    hard: list[Any]
    soft: list[Any]
    free_roll: tuple[bool, bool]
    free_pitch: tuple[bool, bool]
    pivot: tuple[bool, bool] = (False, False)
    lifted: tuple[bool, bool] = (False, False)


class SoleTaskSets:
    """The sole tasks of each contact state (see module docstring).

    Args:
        mink: the mink module.
        sole_tasks: (left, right) full-pose ``FrameTask`` of the sole sites (targets set by the IK).
        foot_roll: (left, right) the leg can roll its foot.
        swing_pitch_cost: weight of a swing sole's pitch as a soft task; None: always hard.
        toe_points: (left, right) :class:`ToePoint` of the soles, with ``toe_off_cost`` the weight of a
            pivoting sole's pitch; None: no sole pivots.
        centres: (left, right) :class:`ToePoint` of the sole centres (no offset), with ``lift_cost`` the
            weight of a swing sole's height; None: a swing sole's position is hard.
    """

    def __init__(
        self,
        mink: Any,
        sole_tasks: list[Any],
        foot_roll: tuple[bool, bool],
        swing_pitch_cost: float | None,
        toe_points: list[ToePoint] | None = None,
        toe_off_cost: float | None = None,
        centres: list[ToePoint] | None = None,
        lift_cost: float | None = None,
    ):
        self.sole_tasks, self.toe_points = sole_tasks, toe_points if toe_off_cost is not None else None
        self.centres = centres if lift_cost is not None else None
        self.lift_cost = lift_cost
        self.heights = [PointCost(c, (0, 0, lift_cost)) for c in centres or []] if lift_cost is not None else []
        #: the sole frame tasks of a flight out of reach, and all its soft sole tasks (:meth:`reaching`)
        self.reach_frames: list[Any] = []
        self.reach_tasks: list[Any] = []
        tasks = sole_tasks

        def pitch(cost: float | None) -> list[Any]:
            if cost is None:
                return []
            w = [0.0, cost, 0.0]
            return [mink.FrameTask(t.frame_name, t.frame_type, position_cost=0.0, orientation_cost=w) for t in tasks]

        self.pitch_tasks, self.toe_pitch_tasks = pitch(swing_pitch_cost), pitch(toe_off_cost)
        flags = (True, False)
        self.sets = {
            (cl, cr, pl, pr): self._tasks((cl, cr), (pl and cl, pr and cr), foot_roll)
            for cl in flags
            for cr in flags
            for pl in flags
            for pr in flags
        }

    def _tasks(self, contact: tuple[bool, bool], pivot: tuple[bool, bool], foot_roll: tuple[bool, bool]) -> SoleTasks:
        hard: list[Any] = []
        soft: list[Any] = []
        toes = self.toe_points is not None
        pivot = (pivot[0] and toes, pivot[1] and toes)
        free_pitch = tuple((bool(self.pitch_tasks) and not c) or p for c, p in zip(contact, pivot, strict=True))
        held = pivot  # position held at the toe point
        lifted = tuple(self.centres is not None and not c for c in contact)
        for i, task in enumerate(self.sole_tasks):
            dropped = ([ROLL] if not foot_roll[i] else []) + ([PITCH] if free_pitch[i] else [])
            dropped += [0, 1, 2] if held[i] or lifted[i] else []
            hard.append(RowsTask(task, tuple(r for r in range(6) if r not in dropped)) if dropped else task)
            if held[i] and self.toe_points is not None:
                hard.append(self.toe_points[i])
            if lifted[i] and self.centres is not None:
                hard.append(RowsTask(self.centres[i], (0, 1)))
                soft.append(self.heights[i])
            if pivot[i]:
                soft.append(self.toe_pitch_tasks[i])
            elif free_pitch[i]:
                soft.append(self.pitch_tasks[i])
            if not foot_roll[i]:
                soft.append(task)
        free_roll = (not foot_roll[0], not foot_roll[1])
        return SoleTasks(hard, soft, free_roll, (free_pitch[0], free_pitch[1]), held, (lifted[0], lifted[1]))

    def reaching(self, mink: Any, cost: float) -> None:
        """Make the set of a flight (no sole in contact) whose soles' poses are soft tasks (position weight
        ``cost`` per m, roll and yaw ``cost`` per rad; with a lift weight, the height that weight and the
        position a world-frame task) instead of hard rows: :meth:`get` with ``reach``."""
        rotation = [cost, 0.0, cost]
        position = cost if self.centres is None else 0.0  # with a lift weight: the centres' tasks below
        self.reach_frames = [
            mink.FrameTask(t.frame_name, t.frame_type, position, rotation, lm_damping=REACH_LM_DAMPING)
            for t in self.sole_tasks
        ]
        points = [PointCost(c, (cost, cost, self.lift_cost), REACH_LM_DAMPING) for c in self.centres or []]
        self.reach_tasks = self.reach_frames + points
        base = [t for t in self.sets[(False, False, False, False)].soft if t not in self.heights]
        self.flight_reach = SoleTasks([], base + self.reach_tasks, (True, True), (True, True))

    def get(self, contact: Any, pivot: Any = (False, False), reach: bool = False) -> SoleTasks:
        """The tasks for ``contact`` (2,) bool [left, right] in contact, ``pivot`` (2,) bool the sole may
        pivot about its toe (only where in contact and toe-off is on); ``reach``: the flight set of
        :meth:`reaching`."""
        if reach:
            return self.flight_reach
        return self.sets[(bool(contact[0]), bool(contact[1]), bool(pivot[0]), bool(pivot[1]))]

    def set_targets(self) -> None:
        """Give the pitch tasks and toe points the sole tasks' targets (call after setting those)."""
        for pitch, task in zip(self.pitch_tasks, self.sole_tasks, strict=False):
            pitch.set_target(task.transform_target_to_world)
        for pitch, task in zip(self.toe_pitch_tasks, self.sole_tasks, strict=False):
            pitch.set_target(task.transform_target_to_world)
        for reach, task in zip(self.reach_frames, self.sole_tasks, strict=False):
            reach.set_target(task.transform_target_to_world)
        for points in (self.toe_points or [], self.centres or []):
            for point, task in zip(points, self.sole_tasks, strict=False):
                target = task.transform_target_to_world
                point.set_target(target.translation(), target.rotation().as_matrix())
