"""The reference of one control tick: plan sample + foot schedule + step feedback -> TickReference.

* CoM: the plan's position translated by the plan shift of the step feedback
  (:class:`~gaitshift.control.feedback.PlanShift`), the plan's velocity and acceleration.
* Stance feet: held where they stand (the reference is unused by the QP's stance constraints).
* Swinging feet: the plan's sole path, translated by the plan shift, plus the foot's own capture-point
  correction ``delta`` blended in with the minimum-jerk profile s(u) of the swing progress u
  (:func:`gaitshift.gait.swing.min_jerk`), with the blend's rates in the velocity and acceleration
  references, ``delta s'(u) / T`` and ``delta s''(u) / T^2`` (``T`` the swing's planned duration; the
  correction's own change from tick to tick is left out). Without them the swing PD's damping held the
  foot back: the G1's foot lagged a lateral correction of 0.3 m by 5-9 cm through its swing
  (``K_d |v| / K_p`` = 60 x 1.5 / 900 = 0.10 m at the blend's peak rate) and landed 4.6 cm short of it
  (docs/robustness.md, "The swing's lag"); on terrain the corrected touchdown is clipped to the planned
  foothold's tread, the sole ``tread_half`` from its edges (a step adjusted onto a stair edge tips the foot)
  plus ``edge_sigmas`` standard deviations of the controller's position along x (the terrain is known in
  the world frame, the controller acts in its estimated one: a heel 3 cm short of the edge lands on it),
  and the clipped correction is written back to the step feedback (the plan shift takes it at touchdown);
  a foothold judged on the map in 2-D (:attr:`PlanSamples.rooms`) clips it to its patch's room instead,
  along x and y (a step adjusted across a block's side tips the foot the same way);
  a swing that spans a flight phase (running) gets an extra lift :func:`swing_lift` that rises fast
  after lift-off and sets down slowly, its peak ``h = clip(lift_per_speed |v|, flight_clearance,
  max_lift)`` growing with the plan's mean CoM speed ``|v|`` over the swing: at speed the hip runs
  away from the trailing foot, and a foot held low drives the knee straight into its limit
  (docs/simulation.md, "Top speed");
  a late foot (planned swing over, no contact yet) keeps descending at ``late_descent_speed``.
* Foot yaws, sole pitches on terrain and the torso heading from the plan (``foot_yaw``, ``heading``,
  :attr:`PlanSamples.foot_pitch`); normal-force caps from the scheduler.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from gaitshift.control.feedback import PlanShift
from gaitshift.control.plan_samples import PlanSamples
from gaitshift.control.schedule import FootScheduler
from gaitshift.control.wbc import TickReference
from gaitshift.gait.swing import min_jerk, min_jerk_rates
from gaitshift.trajectory.contract import Trajectory


@dataclass(frozen=True)
class SwingSettings:
    """Additions to the planned swing paths (see module docstring)."""

    flight_clearance: float = 0.04  # m: least peak extra lift of swings that span a flight
    lift_per_speed: float = 0.09  # s: the peak lift grows as this x the plan's mean CoM speed over the swing
    max_lift: float = 0.18  # m: cap of the speed-scaled lift
    lift_shape: float = 3.0  # n of swing_lift: 1 a parabola, 3 a fast rise and a slow set-down
    late_descent_speed: float = 0.3  # m/s: how fast a late foot keeps going down


def swing_lift(u: float, peak: float, n: float) -> tuple[float, float, float]:
    """Extra lift of a running swing and its first two derivatives in u (m), ``u`` in [0, 1]:
    ``c b(u)`` with ``b = w - w^(n+1)``, ``w = 1 - u``, ``c = peak / max b`` (the peak is at
    ``w* = (n+1)^(-1/n)``). n = 1 is the parabola ``4 peak u (1 - u)``; n = 3 peaks at u = 0.37, leaves
    the floor with slope ``3c`` (1.6x the parabola's) and sets down with slope ``-c`` (0.53x)."""
    w = min(max(1.0 - u, 0.0), 1.0)
    ws = (n + 1.0) ** (-1.0 / n)
    c = peak / (ws - ws ** (n + 1.0))
    return c * (w - w ** (n + 1.0)), -c * (1.0 - (n + 1.0) * w**n), -c * (n + 1.0) * n * w ** (n - 1.0)


def _room_of(rooms: np.ndarray, at: np.ndarray) -> np.ndarray | None:
    """The room (4,) of ``rooms`` (K, 4) that holds the planned landing ``at`` (>= 2,) m, or None."""
    inside = (rooms[:, 0] - 1e-6 <= at[0]) & (at[0] <= rooms[:, 1] + 1e-6)
    inside &= (rooms[:, 2] - 1e-6 <= at[1]) & (at[1] <= rooms[:, 3] + 1e-6)
    k = np.flatnonzero(inside)
    return rooms[k[0]] if len(k) else None


def _keep_on_ground(traj: Trajectory, plan: PlanSamples, i: int, s: int, shift: PlanShift, pos_std: float) -> None:
    """Clip foot ``s``'s corrected touchdown (module docstring), planned at sample ``i``: into its level
    patch's room along x and y, else onto its tread along x; the clip is written back to ``shift``'s
    offset (at touchdown the plan shift takes the correction the foot was given)."""
    land = traj.foot_pos[i, s]
    room = _room_of(plan.rooms, land) if len(plan.rooms) else None
    if room is not None:
        want_xy = land[:2] + shift.shift[:2] + shift.offset[s, :2]
        shift.offset[s, :2] += np.clip(want_xy, room[[0, 2]], room[[1, 3]]) - want_xy
    elif not plan.terrain.flat:
        want = float(land[0]) + shift.shift[0] + shift.offset[s, 0]
        clamped = plan.terrain.clamp_sole(float(land[0]), want, plan.tread_half, shift.settings.edge_sigmas * pos_std)
        shift.offset[s, 0] += clamped - want


def tick_reference(
    traj: Trajectory,
    plan: PlanSamples,
    i: int,
    t: float,
    sched: FootScheduler,
    shift: PlanShift,
    settings: SwingSettings,
    pos_std: float = 0.0,
) -> TickReference:
    """The reference at plan time ``t`` (s), plan sample ``i`` (see module docstring); ``pos_std`` (m):
    the std of the controller's horizontal position along x (its estimate's; 0 on the truth)."""
    foot_ref = traj.foot_pos[i].copy()
    foot_vel = plan.foot_vel[i].copy()
    foot_acc = plan.foot_acc[i].copy()
    for s in (0, 1):
        if sched.stance[s]:
            continue
        dur = sched.swing_duration(s)
        u = sched.swing_progress(t, s)
        if len(plan.rooms) or not plan.terrain.flat:
            _keep_on_ground(traj, plan, sched.landing_sample(s), s, shift, pos_std)
        foot_ref[s] += shift.shift + shift.offset[s] * min_jerk(np.array(u))
        ds, dds = min_jerk_rates(np.array(u))  # the blend's own rates: the reference moves as it is told to
        foot_vel[s] += shift.offset[s] * (float(ds) / dur)
        foot_acc[s] += shift.offset[s] * (float(dds) / dur**2)
        if sched.swing_flight[s] and 0.0 <= u <= 1.0:
            # running swing: fast rise after lift-off, set down with a vertical speed; scaled with speed
            peak = min(
                max(settings.flight_clearance, settings.lift_per_speed * sched.swing_speed[s]), settings.max_lift
            )
            z, zd, zdd = swing_lift(u, peak, settings.lift_shape)
            foot_ref[s, 2] += z
            foot_vel[s, 2] += zd / dur
            foot_acc[s, 2] += zdd / dur**2
        if traj.contact[i, s] and u > 1.0:  # the plan's contact is due, the sole has not landed: descend
            late = t - sched.swing_end[s]
            foot_ref[s, 2] -= settings.late_descent_speed * late
            foot_vel[s] = [0.0, 0.0, -settings.late_descent_speed]
            foot_acc[s] = 0.0
    return TickReference(
        com_pos=traj.com_pos[i] + shift.shift,
        com_vel=traj.com_vel[i],
        com_acc=traj.com_acc[i],
        stance=sched.stance.copy(),
        fz_max=sched.force_caps(t),
        foot_pos=foot_ref,
        foot_vel=foot_vel,
        foot_acc=foot_acc,
        yaw=plan.yaw[i],
        torso_yaw=float(plan.heading[i]),
        yaw_rate=plan.yaw_rate[i],
        torso_yaw_rate=float(plan.heading_rate[i]),
        foot_pitch=plan.foot_pitch[i],
    )
