"""Foot scheduling: the stance/swing state of each foot, from the plan's contact schedule corrected by
the measured contacts, and the normal-force cap of each stance foot.

* Early touchdown: a swinging foot that touches the floor after ``early_touchdown_u`` of its swing
  becomes a stance foot at once.
* Late touchdown: a foot whose planned swing is over but which has not touched keeps swinging (the
  tick reference makes it descend, :mod:`gaitshift.control.reference`) until it touches.
* A stance foot lifts off at the plan's next lift-off time, but never before ``touchdown_ramp`` after
  its own touchdown.
* The normal-force cap of a foot ramps from 0 to full (4 m g) over ``touchdown_ramp`` after its
  touchdown (impact absorption) and from full to 0 over the last ``liftoff_ramp`` of its planned
  stance.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from gaitshift.control.plan_samples import PlanSamples
from gaitshift.trajectory.contract import FLIGHT, Trajectory
from gaitshift.trajectory.window import index_at


@dataclass(frozen=True)
class ScheduleSettings:
    """Timing of the foot state machine (see module docstring)."""

    touchdown_ramp: float = 0.03  # s: normal-force cap ramp after touchdown
    liftoff_ramp: float = 0.01  # s: unloading before a planned lift-off
    early_touchdown_u: float = 0.6  # swing progress after which a contact counts as touchdown


def next_time(times: np.ndarray, t: float) -> float:
    """First of the increasing ``times`` (s) at or after ``t`` (1 ns tolerance), or inf."""
    i = np.searchsorted(times, t - 1e-9)
    return float(times[i]) if i < len(times) else math.inf


class FootScheduler:
    """Stance/swing state of each foot (see module docstring).

    State, per foot (left, right): ``stance`` (2,) bool; ``t_touch`` time of the last touchdown (s, -1
    before any); ``swing_start``/``swing_end`` the current (or last) swing's lift-off and planned
    touchdown times, s; ``swing_flight`` whether that swing spans a flight phase of the plan;
    ``lift_at`` the planned lift-off that ends the current stance, s; ``swing_speed`` the plan's mean
    horizontal CoM speed over the current swing, m/s; ``open_swing`` a swing the plan holds no landing
    for (a re-plan off the tick that comes late: the swing ends at the plan's end until the new plan
    gives its touchdown, so that no time left is infinite).

    Args:
        traj: the plan; ``plan`` its :class:`PlanSamples`.
        settings: ramps and early-touchdown threshold.
        weight: robot weight m g, N; the full force cap is 4 m g.
    """

    def __init__(self, traj: Trajectory, plan: PlanSamples, settings: ScheduleSettings, weight: float) -> None:
        self.traj = traj
        self.plan = plan
        self.settings = settings
        self.full = 4.0 * weight
        self.stance = traj.contact[0].copy()  # the plan's first contact flags (the plant is never read)
        self.t_touch = np.full(2, -1.0)
        self.swing_start = np.zeros(2)
        self.swing_end = np.zeros(2)
        self.open_swing = np.zeros(2, bool)
        self.swing_flight = np.zeros(2, bool)
        self.swing_speed = np.zeros(2)
        self.lift_at = np.array([next_time(plan.lift[k], 0.0) for k in (0, 1)])

    def retarget(self, traj: Trajectory, plan: PlanSamples) -> None:
        """Follow a new plan (a re-plan, or a streaming plan that grew) from now on; the current foot
        states are kept, and a stance foot whose lift-off the old plan did not hold yet takes it from
        the new one; a swinging foot takes the new plan's touchdown time."""
        self.traj, self.plan = traj, plan
        for s in (0, 1):
            if self.stance[s]:
                if not math.isfinite(self.lift_at[s]):
                    self.lift_at[s] = next_time(plan.lift[s], max(self.t_touch[s], self.swing_end[s], 0.0))
            elif self.open_swing[s]:
                self._set_landing(s, next_time(plan.land[s], self.swing_start[s]))

    def swing_duration(self, side: int) -> float:
        """Planned duration of the current (or last) swing of ``side``, s (at least 1 us)."""
        return float(max(self.swing_end[side] - self.swing_start[side], 1e-6))

    def landing_sample(self, side: int) -> int:
        """The plan sample of the planned touchdown of ``side``'s current (or last) swing; the plan's last
        sample when the plan ends before it (a re-plan that comes late, off the tick: ``retarget`` then
        takes the new plan's touchdown)."""
        return index_at(self.traj, min(float(self.swing_end[side]), float(self.traj.t[-1])))

    def swing_progress(self, t: float, side: int) -> float:
        """u = (t - lift-off) / (planned touchdown - lift-off) of the current swing of ``side``; u > 1
        when the touchdown is late."""
        return float((t - self.swing_start[side]) / self.swing_duration(side))

    def update(self, t: float, i: int, touching: np.ndarray) -> None:
        """Advance to plan time ``t`` (s), plan sample ``i``, with the measured sole contacts (2,)."""
        planned = self.traj.contact[i]
        for s in (0, 1):
            if self.stance[s]:
                if t >= self.lift_at[s] - 1e-9 and t >= self.t_touch[s] + self.settings.touchdown_ramp:
                    self._lift_off(t, s)
            elif touching[s] and (planned[s] or self.swing_progress(t, s) >= self.settings.early_touchdown_u):
                self.stance[s] = True
                self.t_touch[s] = t
                # the stance lasts until the plan's lift-off that follows the planned touchdown
                self.lift_at[s] = next_time(self.plan.lift[s], max(t, self.swing_end[s]))

    def _set_landing(self, s: int, t_land: float) -> None:
        """The planned touchdown of ``s``'s swing; the plan's end when the plan holds none (``open_swing``)."""
        self.open_swing[s] = not math.isfinite(t_land)
        self.swing_end[s] = float(self.traj.t[-1]) if self.open_swing[s] else t_land

    def _lift_off(self, t: float, s: int) -> None:
        self.stance[s] = False
        self.swing_start[s] = t
        self._set_landing(s, next_time(self.plan.land[s], t))
        j0 = index_at(self.traj, t)
        j1 = index_at(self.traj, min(self.swing_end[s], float(self.traj.t[-1])))
        self.swing_flight[s] = bool(np.any(self.traj.phase[j0 : j1 + 1] == FLIGHT))
        vel = self.traj.com_vel[j0 : j1 + 1, :2]
        self.swing_speed[s] = float(np.linalg.norm(vel.mean(axis=0))) if len(vel) else 0.0

    def force_caps(self, t: float) -> np.ndarray:
        """Cap on the total normal force of each foot at time ``t``, N, (2,); ~0 for swinging feet."""
        caps = np.zeros(2)
        for s in (0, 1):
            if not self.stance[s]:
                continue
            ramp = self.settings.touchdown_ramp
            up = 1.0 if self.t_touch[s] < 0 else min(1.0, (t - self.t_touch[s]) / ramp)
            down = min(1.0, max(0.0, (self.lift_at[s] - t) / self.settings.liftoff_ramp))
            caps[s] = self.full * min(up, down) + 1e-3
        return caps
