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
  its limit at lift-off. A sole in contact is always flat (all its rows hard).

The soft range of a joint (mjlab's ``soft_joint_pos_limits``): centre +- f x half range, f =
``RobotConfig.soft_joint_fraction`` (robot YAML ``limits.soft_joint_fraction``, 0.9 by default).
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

#: rows of a sole task: position x, y, z, rotation about the sole's x (roll), y (pitch), z (yaw)
ROLL, PITCH = 3, 4


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


@dataclass(frozen=True)
class SoleTasks:
    """The sole tasks of one contact state: ``hard`` (equality constraints), ``soft`` (weighted tasks) and,
    per side (left, right), whether roll and pitch are free (left out of the orientation error)."""

    hard: list[Any]
    soft: list[Any]
    free_roll: tuple[bool, bool]
    free_pitch: tuple[bool, bool]


class SoleTaskSets:
    """The sole tasks of each contact state (see module docstring).

    Args:
        mink: the mink module.
        sole_tasks: (left, right) full-pose ``FrameTask`` of the sole sites (targets set by the IK).
        foot_roll: (left, right) the leg can roll its foot.
        swing_pitch_cost: weight of a swing sole's pitch as a soft task; None: always hard.
    """

    def __init__(self, mink: Any, sole_tasks: list[Any], foot_roll: tuple[bool, bool], swing_pitch_cost: float | None):
        self.sole_tasks = sole_tasks
        cost = [0.0, swing_pitch_cost, 0.0]
        self.pitch_tasks = (
            [mink.FrameTask(t.frame_name, t.frame_type, position_cost=0.0, orientation_cost=cost) for t in sole_tasks]
            if swing_pitch_cost is not None
            else []
        )
        self.sets = {
            (left, right): self._tasks((left, right), foot_roll) for left in (True, False) for right in (True, False)
        }

    def _tasks(self, contact: tuple[bool, bool], foot_roll: tuple[bool, bool]) -> SoleTasks:
        hard: list[Any] = []
        soft: list[Any] = []
        free_pitch = tuple(bool(self.pitch_tasks) and not c for c in contact)
        for i, task in enumerate(self.sole_tasks):
            dropped = ([ROLL] if not foot_roll[i] else []) + ([PITCH] if free_pitch[i] else [])
            hard.append(RowsTask(task, tuple(r for r in range(6) if r not in dropped)) if dropped else task)
            if not foot_roll[i]:
                soft.append(task)
            if free_pitch[i]:
                soft.append(self.pitch_tasks[i])
        free_roll = (not foot_roll[0], not foot_roll[1])
        return SoleTasks(hard, soft, free_roll, (free_pitch[0], free_pitch[1]))

    def get(self, contact: Any) -> SoleTasks:
        """The tasks for ``contact`` (2,) bool [left, right] in contact."""
        return self.sets[(bool(contact[0]), bool(contact[1]))]

    def set_targets(self) -> None:
        """Give the swing pitch tasks the sole tasks' targets (call after setting those)."""
        for pitch, task in zip(self.pitch_tasks, self.sole_tasks, strict=False):
            pitch.set_target(task.transform_target_to_world)
