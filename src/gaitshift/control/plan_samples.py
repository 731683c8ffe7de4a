"""Per-sample references derived once from a plan, for the foot scheduler and the tick reference."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from gaitshift.gait.swing import foot_yaws
from gaitshift.models.terrain import FLAT, Terrain
from gaitshift.trajectory.contract import Trajectory


@dataclass(frozen=True)
class PlanSamples:
    """What the closed loop needs from a plan beyond its own arrays.

    Attributes:
        foot_vel, foot_acc: (N, 2, 3) sole-centre velocity (m/s) and acceleration (m/s^2), central
            differences (``np.gradient``) of ``traj.foot_pos``.
        yaw: (N, 2) rad, yaw of each foot (the plan's ``foot_yaw``); heading: (N,) rad, the plan's
            heading (the torso's and pelvis' yaw reference).
        yaw_rate: (N, 2) rad/s and heading_rate: (N,) rad/s, their central differences (of the
            unwrapped angles): the velocity references of the orientation tasks, so that a turn at a
            constant rate is tracked without the PD's steady lag ``kd/kp * rate``.
        foot_pitch: (N, 2) rad, inclination of each sole, positive toe up: in contact the slope of the
            plan's terrain (``meta["terrain"]``) under its foothold, in a swing the minimum-jerk blend
            from the lift-off foothold's to the touchdown foothold's (as the yaws,
            :func:`gaitshift.gait.swing.foot_yaws`); zero on flat ground.
        terrain: the plan's terrain; tread_half: half the sole length (the plan's foot or the robot's sole,
            the longer) plus the plan's edge clearance,
            m: how far a corrected touchdown stays from the edges of its tread (control/reference.py).
        lift, land: per foot (left, right), the plan times (s) of its lift-offs and touchdowns
            (first sample after the contact flag changes), increasing.
        rooms: (K, 4) m, rows (x_lo, x_hi, y_lo, y_hi): where the centre of a foothold judged on the map
            in 2-D may move and its patch stay level (``meta["foothold_rooms"]``,
            :class:`gaitshift.control.perception.patches.Patch`); a corrected touchdown stays in its
            foothold's room (control/reference.py).
    """

    foot_vel: np.ndarray
    foot_acc: np.ndarray
    yaw: np.ndarray
    heading: np.ndarray
    yaw_rate: np.ndarray
    heading_rate: np.ndarray
    lift: tuple[np.ndarray, np.ndarray]
    land: tuple[np.ndarray, np.ndarray]
    foot_pitch: np.ndarray
    terrain: Terrain = FLAT
    tread_half: float = 0.0
    rooms: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))

    @classmethod
    def from_trajectory(cls, traj: Trajectory, sole_length: float = 0.0) -> PlanSamples:
        """Derive the samples of ``traj`` (see the class docstring); ``sole_length`` (m): the robot's
        sole length, when it is longer than the plan's foot, keeps the whole real sole on its tread."""
        dt = traj.dt
        fp = traj.foot_pos
        fv = np.gradient(fp, dt, axis=0)
        fa = np.gradient(fv, dt, axis=0)
        c = traj.contact
        t = traj.t
        lift = (t[1:][c[:-1, 0] & ~c[1:, 0]], t[1:][c[:-1, 1] & ~c[1:, 1]])
        land = (t[1:][~c[:-1, 0] & c[1:, 0]], t[1:][~c[:-1, 1] & c[1:, 1]])
        yaw_rate = np.gradient(np.unwrap(traj.foot_yaw, axis=0), dt, axis=0) if len(t) > 1 else np.zeros((len(t), 2))
        heading_rate = np.gradient(np.unwrap(traj.heading), dt) if len(t) > 1 else np.zeros(len(t))
        terrain = Terrain.from_list(traj.meta.get("terrain"))
        pitch = np.zeros((len(t), 2))
        if not terrain.flat:
            fs = traj.footsteps.copy()
            fs[:, 3] = np.arctan(terrain.slope(fs[:, 0]))  # each foothold's pitch in the yaw column
            pitch = foot_yaws(c.astype(bool), fp, fs, traj.footstep_side)
        foot = max(float(traj.meta.get("foot_size", [0.0])[0]), sole_length)
        half = 0.5 * foot + float(traj.meta.get("edge_clearance", 0.0))
        return cls(
            terrain=terrain,
            tread_half=half,
            rooms=np.asarray(traj.meta.get("foothold_rooms") or np.zeros((0, 4)), float).reshape(-1, 4),
            foot_pitch=pitch,
            foot_vel=fv,
            foot_acc=fa,
            yaw=traj.foot_yaw,
            heading=traj.heading,
            yaw_rate=yaw_rate,
            heading_rate=heading_rate,
            lift=lift,
            land=land,
        )
