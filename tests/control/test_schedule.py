"""Foot scheduler: stance/swing from the plan's contact schedule and the measured contacts, and the
normal-force caps.

Checked against the plan itself: replaying the planned contacts as measurements must reproduce the
planned contact flags sample by sample; an early or missing touchdown must switch (or not) at the
documented swing progress; the caps must follow the documented linear ramps, computed here by hand.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import gaitshift
from gaitshift.control.plan_samples import PlanSamples
from gaitshift.control.schedule import FootScheduler, ScheduleSettings, next_time
from gaitshift.trajectory.contract import FLIGHT

WEIGHT = 300.0  # N


@pytest.fixture(scope="module")
def walk():
    traj = gaitshift.plan("g1-walk")
    return traj, PlanSamples.from_trajectory(traj)


def _scheduler(traj, plan, **settings):
    return FootScheduler(traj, plan, ScheduleSettings(**settings), WEIGHT)


def _replay(sched, traj, upto=None):
    """Feed the planned contacts as measurements; returns the stance (N, 2) after each update."""
    n = len(traj) if upto is None else upto
    out = np.zeros((n, 2), bool)
    for i in range(n):
        sched.update(float(traj.t[i]), i, traj.contact[i])
        out[i] = sched.stance
    return out


def _swinging_side(traj):
    """The foot (0 left, 1 right) that the plan lifts first."""
    lifts = traj.contact[:-1] & ~traj.contact[1:]
    return int(np.argmax(lifts[np.flatnonzero(lifts.any(axis=1))[0]]))


def _first_swing(traj, side):
    """(lift-off index, touchdown index) of the first swing of ``side``."""
    c = traj.contact[:, side]
    i0 = int(np.flatnonzero(c[:-1] & ~c[1:])[0]) + 1
    i1 = i0 + int(np.flatnonzero(c[i0:])[0])
    return i0, i1


def test_replaying_the_planned_contacts_reproduces_the_plan(walk):
    traj, plan = walk
    stance = _replay(_scheduler(traj, plan), traj)
    np.testing.assert_array_equal(stance, traj.contact)


def test_running_swings_are_marked_as_spanning_a_flight():
    traj = gaitshift.plan("g1-run")
    sched = _scheduler(traj, PlanSamples.from_trajectory(traj))
    flags = []
    for i in range(len(traj)):
        before = sched.stance.copy()
        sched.update(float(traj.t[i]), i, traj.contact[i])
        for s in np.flatnonzero(before & ~sched.stance):
            i1 = round(sched.swing_end[s] / traj.dt)
            flags.append((bool(sched.swing_flight[s]), bool(np.any(traj.phase[i : i1 + 1] == FLIGHT))))
    assert len(flags) >= 10
    assert all(got == want for got, want in flags)
    assert any(got for got, _ in flags)


def test_contact_after_the_early_touchdown_threshold_lands_the_foot(walk):
    traj, plan = walk
    side = _swinging_side(traj)
    i0, i1 = _first_swing(traj, side)
    for u, lands in ((0.5, False), (0.65, True)):
        sched = _scheduler(traj, plan, early_touchdown_u=0.6)
        _replay(sched, traj, upto=i0 + 1)
        assert not sched.stance[side]
        t = float(traj.t[i0] + u * (traj.t[i1] - traj.t[i0]))
        i = round(t / traj.dt)
        touching = traj.contact[i].copy()
        touching[side] = True
        sched.update(t, i, touching)
        assert sched.swing_progress(t, side) == pytest.approx(u, abs=2e-3)
        assert bool(sched.stance[side]) is lands
        if lands:
            assert sched.t_touch[side] == t
            # the stance lasts until the plan's lift-off after the planned touchdown
            assert sched.lift_at[side] == next_time(plan.lift[side], float(traj.t[i1]))


def test_a_foot_without_contact_keeps_swinging_past_its_planned_touchdown(walk):
    traj, plan = walk
    side = _swinging_side(traj)
    i0, i1 = _first_swing(traj, side)
    sched = _scheduler(traj, plan)
    for i in range(i1 + 50):
        touching = traj.contact[i].copy()
        if i >= i0:
            touching[side] = False
        sched.update(float(traj.t[i]), i, touching)
    t = float(traj.t[i1 + 49])
    assert not sched.stance[side]
    expected = (t - traj.t[i0]) / (traj.t[i1] - traj.t[i0])
    assert sched.swing_progress(t, side) == pytest.approx(expected, rel=1e-6)
    assert sched.swing_progress(t, side) > 1.0


def test_force_cap_ramps_up_after_touchdown_and_down_before_lift_off(walk):
    traj, plan = walk
    side = _swinging_side(traj)
    i0, i1 = _first_swing(traj, side)
    ramp_up, ramp_down = 0.03, 0.01
    sched = _scheduler(traj, plan, touchdown_ramp=ramp_up, liftoff_ramp=ramp_down)
    _replay(sched, traj, upto=i1 + 1)
    full = 4.0 * WEIGHT
    t_td = float(traj.t[i1])
    t_lift = float(sched.lift_at[side])
    assert sched.force_caps(t_td - 0.01)[1 - side] == pytest.approx(full + 1e-3)  # the other foot: full
    for frac in (0.0, 0.25, 0.5, 1.0, 2.0):
        assert sched.force_caps(t_td + frac * ramp_up)[side] == pytest.approx(full * min(frac, 1.0) + 1e-3)
    for frac in (1.0, 0.5, 0.0):
        assert sched.force_caps(t_lift - frac * ramp_down)[side] == pytest.approx(full * frac + 1e-3)
    swinging = _scheduler(traj, plan)
    _replay(swinging, traj, upto=i0 + 1)
    assert not swinging.stance[side] and swinging.force_caps(float(traj.t[i0]))[side] == 0.0


def test_a_swing_the_plan_holds_no_landing_for_ends_at_the_plans_end_until_a_plan_gives_it(walk):
    """A plan cut before a swing's landing (a re-plan off the tick that comes late): the swing ends at the
    plan's end, finite (the time left feeds the step feedback), and takes the touchdown of the next plan
    that holds one; the landing sample is the plan's touchdown sample."""
    traj, plan = walk
    side = _swinging_side(traj)
    i0, i1 = _first_swing(traj, side)
    land = list(plan.land)
    land[side] = land[side][:0]  # the plan holds no landing of this foot
    cut = dataclasses.replace(plan, land=tuple(land))
    sched = _scheduler(traj, cut)
    _replay(sched, traj, upto=i0 + 1)
    assert not sched.stance[side] and sched.open_swing[side]
    assert sched.swing_end[side] == traj.t[-1] and sched.landing_sample(side) == len(traj) - 1
    sched.retarget(traj, plan)  # the new plan holds the landing
    assert not sched.open_swing[side] and sched.swing_end[side] == pytest.approx(traj.t[i1])
    assert sched.landing_sample(side) == i1
