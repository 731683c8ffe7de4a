"""The tick reference: plan sample + scheduler state + plan shift.

The swing additions are checked by differentiating the produced positions numerically in time (the
velocity and acceleration references must be their derivatives), and the CoM and stance references
against the plan sample plus the shift, computed here.
"""

from __future__ import annotations

import numpy as np
import pytest

import gaitshift
from gaitshift.control.feedback import CaptureSettings, PlanShift
from gaitshift.control.plan_samples import PlanSamples
from gaitshift.control.reference import SwingSettings, tick_reference
from gaitshift.control.schedule import FootScheduler, ScheduleSettings
from gaitshift.gait.swing import min_jerk


@pytest.fixture(scope="module")
def run_plan():
    traj = gaitshift.plan("g1-run")
    return traj, PlanSamples.from_trajectory(traj)


def _state(traj, plan, swing_flight):
    """Scheduler with the right foot swinging from t = 1.0 s to 1.4 s, the left foot in stance; a shift."""
    sched = FootScheduler(traj, plan, ScheduleSettings(), 300.0)
    sched.stance[:] = (True, False)
    sched.swing_start[1], sched.swing_end[1] = 1.0, 1.4
    sched.swing_flight[1] = swing_flight
    shift = PlanShift(CaptureSettings(), omega=4.0)
    shift.shift[:] = (0.02, -0.01, 0.0)
    shift.offset[1] = (0.03, 0.01, 0.0)
    return sched, shift


def test_com_and_stance_foot_follow_the_shifted_plan_sample(run_plan):
    traj, plan = run_plan
    sched, shift = _state(traj, plan, swing_flight=False)
    i = 1200
    ref = tick_reference(traj, plan, i, 1.2, sched, shift, SwingSettings())
    np.testing.assert_array_equal(ref.com_pos, traj.com_pos[i] + shift.shift)
    np.testing.assert_array_equal(ref.com_vel, traj.com_vel[i])
    np.testing.assert_array_equal(ref.foot_pos[0], traj.foot_pos[i, 0])
    u = (1.2 - 1.0) / 0.4
    np.testing.assert_allclose(ref.foot_pos[1], traj.foot_pos[i, 1] + shift.shift + shift.offset[1] * min_jerk(u))
    assert ref.torso_yaw == pytest.approx(plan.yaw[i].mean())
    np.testing.assert_array_equal(ref.stance, [True, False])


def test_flight_bump_velocity_and_acceleration_are_the_time_derivatives_of_its_height(run_plan):
    traj, plan = run_plan
    sched, shift = _state(traj, plan, swing_flight=True)
    shift.offset[1] = 0.0
    settings = SwingSettings(flight_clearance=0.04, lift_per_speed=0.0, lift_shape=1.0)  # the parabola
    i, h = 1200, 1e-4  # plan sample held fixed: only the bump depends on t

    def z(t):
        return tick_reference(traj, plan, i, t, sched, shift, settings).foot_pos[1, 2]

    for t in (1.05, 1.2, 1.33):
        ref = tick_reference(traj, plan, i, t, sched, shift, settings)
        vel = ref.foot_vel[1, 2] - plan.foot_vel[i, 1, 2]
        acc = ref.foot_acc[1, 2] - plan.foot_acc[i, 1, 2]
        assert vel == pytest.approx((z(t + h) - z(t - h)) / (2 * h), rel=1e-6, abs=1e-9)
        assert acc == pytest.approx((z(t + h) - 2 * z(t) + z(t - h)) / h**2, rel=1e-4)
    u = 0.5  # apex: the full clearance above the plan
    assert z(1.2) - traj.foot_pos[i, 1, 2] == pytest.approx(0.04 * 4 * u * (1 - u))


def test_correction_blend_velocity_and_acceleration_are_the_time_derivatives_of_its_position(run_plan):
    traj, plan = run_plan
    sched, shift = _state(traj, plan, swing_flight=False)
    shift.offset[1] = (0.05, 0.3, 0.0)  # a lateral push's correction
    i, h = 1200, 1e-4  # plan sample held fixed: only the blend depends on t

    def xy(t):
        return tick_reference(traj, plan, i, t, sched, shift, SwingSettings()).foot_pos[1, :2]

    for t in (1.05, 1.2, 1.33):
        ref = tick_reference(traj, plan, i, t, sched, shift, SwingSettings())
        vel = ref.foot_vel[1, :2] - plan.foot_vel[i, 1, :2]
        acc = ref.foot_acc[1, :2] - plan.foot_acc[i, 1, :2]
        np.testing.assert_allclose(vel, (xy(t + h) - xy(t - h)) / (2 * h), rtol=1e-6, atol=1e-9)
        np.testing.assert_allclose(acc, (xy(t + h) - 2 * xy(t) + xy(t - h)) / h**2, rtol=1e-4, atol=1e-6)
    # the blend's peak rate at mid-swing: 1.875 x the correction over the swing's 0.4 s
    mid = tick_reference(traj, plan, i, 1.2, sched, shift, SwingSettings())
    assert mid.foot_vel[1, 1] - plan.foot_vel[i, 1, 1] == pytest.approx(1.875 * 0.3 / 0.4)


def test_a_late_foot_keeps_descending_at_the_set_speed(run_plan):
    traj, plan = run_plan
    sched, shift = _state(traj, plan, swing_flight=False)
    i = int(np.flatnonzero(traj.contact[:, 1])[-1])  # a sample where the plan has the right foot down
    settings = SwingSettings(late_descent_speed=0.3)
    ref = tick_reference(traj, plan, i, 1.5, sched, shift, settings)  # 0.1 s after the planned touchdown
    base = traj.foot_pos[i, 1, 2] + shift.shift[2] + shift.offset[1, 2]
    assert ref.foot_pos[1, 2] == pytest.approx(base - 0.3 * 0.1)
    np.testing.assert_array_equal(ref.foot_vel[1], [0.0, 0.0, -0.3])
    np.testing.assert_array_equal(ref.foot_acc[1], 0.0)


def test_swing_lift_is_the_parabola_for_n1_and_its_derivatives_match_finite_differences():
    from gaitshift.control.reference import swing_lift

    u = np.linspace(0.0, 1.0, 41)
    for peak, n in ((0.04, 1.0), (0.15, 3.0)):
        z = np.array([swing_lift(x, peak, n) for x in u])
        assert abs(z[0, 0]) < 1e-15 and abs(z[-1, 0]) < 1e-15
        assert np.isclose(z[:, 0].max(), peak, rtol=1e-3)
        h = 1e-6
        for x in (0.2, 0.5, 0.8):
            zp, zm = swing_lift(x + h, peak, n), swing_lift(x - h, peak, n)
            assert np.isclose(swing_lift(x, peak, n)[1], (zp[0] - zm[0]) / (2 * h), rtol=1e-6)
            assert np.isclose(swing_lift(x, peak, n)[2], (zp[1] - zm[1]) / (2 * h), rtol=1e-5)
    par = np.array([swing_lift(x, 0.04, 1.0)[0] for x in u])
    assert np.allclose(par, 4 * 0.04 * u * (1 - u), atol=1e-15)


def test_a_correction_stays_in_the_room_of_its_foothold_on_a_flat_patch(run_plan):
    """A foothold chosen on a flat patch of the map (``meta["foothold_rooms"]``): the corrected touchdown
    is clipped into its room along x and y, and the clip written back to the step feedback."""
    from dataclasses import replace

    traj, plan = run_plan
    sched, shift = _state(traj, plan, swing_flight=False)
    land = traj.foot_pos[sched.landing_sample(1), 1]
    room = np.array([land[0] - 0.01, land[0] + 0.02, land[1] - 0.005, land[1] + 0.003])
    roomy = replace(plan, rooms=room[None, :])
    shift.offset[1] = (0.08, -0.04, 0.0)
    tick_reference(traj, roomy, 1200, 1.2, sched, shift, SwingSettings())
    want = land[:2] + shift.shift[:2] + shift.offset[1, :2]  # where the touchdown now goes
    np.testing.assert_allclose(want, [land[0] + 0.02, land[1] - 0.005], atol=1e-12)  # x high, y low: clipped
    far = replace(plan, rooms=(room + 1.0)[None, :])  # a room elsewhere: not this foothold's
    shift.offset[1] = (0.08, -0.04, 0.0)
    tick_reference(traj, far, 1200, 1.2, sched, shift, SwingSettings())
    np.testing.assert_array_equal(shift.offset[1], (0.08, -0.04, 0.0))
