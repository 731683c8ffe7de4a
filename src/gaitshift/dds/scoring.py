"""The robot process scores the brain's state estimate against its truth (``gaitshift dds robot --summary``).

The robot keeps the truth of its last :data:`KEEP` ticks (the pelvis position and quaternion w x y z, its
linear velocity in the world frame, the feet touching the floor: :mod:`gaitshift.sim.contacts`), taken
when the tick's state is written; each valid :class:`~gaitshift.dds.own_messages.Estimate_` is matched to
the truth of the ``LowState_`` tick the brain acted on (``Estimate_.tick``) and scored:

* ``est_velocity_rmse`` m/s: the pelvis velocity's error, each velocity in its own heading frame (the
  yaw removed: the estimator's yaw is its own, unobservable and drifting), the RMS of the 3-vector's norm;
* ``est_tilt_rmse`` rad: the angle between the vertical as the estimate and as the truth see it in the
  pelvis frame (yaw-free);
* ``est_height_rmse`` m: the pelvis height;
* ``est_contact_accuracy``: the share of (tick, foot) pairs whose contact flag equals the truth's;
* ``est_yaw_drift`` rad and ``est_position_drift`` m: at the last scored tick, the yaw error and the
  horizontal position error (the estimate's displacement against the truth's), both minus their value
  at the first scored tick (the controller's world frame starts at its plan's start pose, not the
  robot's).

NaN (written as null) when no estimate was scored. The truth never leaves the robot process.
"""

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from gaitshift.common.rotations import roll_pitch_yaw, tilt_error

__all__ = ["KEEP", "EstimateScore", "ScoreSummary", "score_recordings", "yaw_of"]

#: ticks of truth kept (8 s at 2 ms): an estimate about an older tick is counted as unmatched
KEEP = 4096


def yaw_of(quat: np.ndarray) -> float:
    """The yaw, rad, of a unit quaternion w x y z (z-y-x Euler angles)."""
    return float(roll_pitch_yaw(quat)[2])


def _heading_velocity(vel: np.ndarray, yaw: float) -> np.ndarray:
    """The world-frame velocity (3,) m/s in the heading frame of ``yaw`` rad."""
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([c * vel[0] + s * vel[1], -s * vel[0] + c * vel[1], vel[2]])


@dataclass(frozen=True)
class ScoreSummary:
    """The score (module docstring). ``estimates_received``: Estimate_ taken; ``estimates_scored``: valid
    ones matched to a truth; ``estimates_unmatched``: valid ones whose tick was not (or no longer) kept."""

    estimates_received: int
    estimates_scored: int
    estimates_unmatched: int
    est_velocity_rmse: float
    est_tilt_rmse: float
    est_height_rmse: float
    est_contact_accuracy: float
    est_yaw_drift: float
    est_position_drift: float


def _rms(a: Any) -> float:
    """The root mean square of ``a``; NaN when empty."""
    a = np.asarray(a, float)
    return float(np.sqrt(np.mean(np.square(a)))) if a.size else math.nan


class EstimateScore:
    """The truth of the last :data:`KEEP` ticks and the running score (module docstring)."""

    def __init__(self, keep: int = KEEP) -> None:
        self.keep = keep
        self.tick = np.full(keep, -1, np.int64)
        self.pose = np.zeros((keep, 7))
        self.vel = np.zeros((keep, 3))
        self.touch = np.zeros((keep, 2), bool)
        self.received = self.unmatched = 0
        self.sq_vel: list[float] = []
        self.tilt: list[float] = []
        self.height: list[float] = []
        self.contact_hits = 0
        self.first: tuple[float, np.ndarray] | None = None  # yaw error, xy offset at the first scored tick
        self.last: tuple[float, np.ndarray] | None = None

    def truth(self, k: int, qpos: np.ndarray, qvel: np.ndarray, touching: np.ndarray) -> None:
        """Keep tick ``k``'s truth: ``qpos[:7]`` (the pelvis position m, quaternion w x y z), ``qvel[:3]``
        m/s world frame, ``touching`` (2,) bool."""
        i = k % self.keep
        self.tick[i], self.pose[i], self.vel[i], self.touch[i] = k, qpos[:7], qvel[:3], touching[:2]

    def add(self, msg: Any) -> None:
        """Score one Estimate_ (ignored when not valid; counted unmatched when its tick is not kept)."""
        self.received += 1
        if msg.valid:
            self.score(int(msg.tick), msg.base_pos, msg.base_quat, msg.base_vel, list(msg.contact[:2]))

    def score(self, tick: int, base_pos: Any, base_quat: Any, base_vel: Any, contact: Any) -> None:
        """Score the estimate of tick ``tick``: the pelvis position (3,) m, quaternion (4,) w x y z, linear
        velocity (3,) m/s in the estimate's frame, the contact flags (2,) (unmatched when the tick's truth
        is not kept)."""
        i = tick % self.keep
        if self.tick[i] != tick:
            self.unmatched += 1
            return
        pos, quat = np.asarray(base_pos, float), np.asarray(base_quat, float)
        quat = quat / max(float(np.linalg.norm(quat)), 1e-12)
        t_pos, t_quat = self.pose[i, :3], self.pose[i, 3:]
        yaw_e, yaw_t = yaw_of(quat), yaw_of(t_quat)
        dv = _heading_velocity(np.asarray(base_vel, float), yaw_e) - _heading_velocity(self.vel[i], yaw_t)
        self.sq_vel.append(float(dv @ dv))
        self.tilt.append(float(tilt_error(quat, t_quat)))
        self.height.append(float(pos[2] - t_pos[2]))
        flags = np.array(list(contact), int) != 0  # uint8[2]: bytes once off the wire, a list before
        self.contact_hits += int(np.sum(flags == self.touch[i]))
        dyaw = math.remainder(yaw_e - yaw_t, math.tau)
        self.last = (dyaw, pos[:2] - t_pos[:2])
        self.first = self.first or self.last

    def summary(self) -> ScoreSummary:
        """The score so far (NaN when nothing was scored)."""
        n = len(self.sq_vel)
        nan = math.nan
        drift_yaw = drift_pos = nan
        if self.first is not None and self.last is not None:
            drift_yaw = math.remainder(self.last[0] - self.first[0], math.tau)
            drift_pos = float(np.linalg.norm(self.last[1] - self.first[1]))
        return ScoreSummary(
            self.received,
            n,
            self.unmatched,
            _rms(np.sqrt(self.sq_vel)),
            _rms(self.tilt),
            _rms(self.height),
            self.contact_hits / (2 * n) if n else nan,
            drift_yaw,
            drift_pos,
        )


def score_recordings(brain: Any, robot: Any) -> ScoreSummary:
    """The robot's score (module docstring) of the estimates in a brain's recording against the truth in
    the robot's (:mod:`gaitshift.dds.record`; ``brain``, ``robot``: the loaded files): what the robot's
    summary says of a run, from its two files alone (``estimates_received`` counts the brain's rows)."""
    ticks = np.asarray(robot["tick"], np.int64)
    score = EstimateScore(keep=int(ticks.max(initial=0)) + 1)
    for k, qpos, qvel, touching in zip(ticks, robot["qpos"], robot["qvel"], robot["touching"], strict=True):
        score.truth(int(k), qpos, qvel, touching > 0.5)
    est = np.asarray(brain["estimated"]) > 0.5
    score.received = len(est)
    for k, qpos, qvel, contact in zip(
        np.asarray(brain["tick"], np.int64)[est],
        brain["est_qpos"][est],
        brain["est_qvel"][est],
        brain["est_contact"][est],
        strict=True,
    ):
        score.score(int(k), qpos[:3], qpos[3:7], qvel[:3], contact > 0.5)
    return score.summary()
