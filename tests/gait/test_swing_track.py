"""The shared swing-foot tracker (gait.swing_track): from rest a swing is the minimum-jerk blend and
height sextic of gait.swing; the analytic rates and accelerations are the time derivatives of the
positions; a re-target mid-swing keeps position, velocity and acceleration continuous (C2), lands at
rest on the new target, and when the touchdown sample moves the height still passes the apex at the
new mid-swing time.

Oracles: :func:`gaitshift.gait.swing.swing_path` (a separate evaluation of the paper 003 swing) and
central finite differences of the sampled positions.
"""

import copy

import numpy as np
import pytest

from gaitshift.gait.swing import min_jerk, swing_path
from gaitshift.gait.swing_track import FootTrack, Swing, height_from_state

DT = 0.002


def _swing(i_lift=10, i_land=210):
    return Swing(i_lift, i_land, np.array([0.0, 0.1, 0.0, 0.0]), np.array([0.4, 0.12, 0.05, 0.3]), DT, 0.08)


def _finite_differences(sw, idx, h=0.01):
    """Central first and second differences (step ``h`` samples) of the positions at ``idx`` (n,)
    -> (n, 4) each."""
    p = sw.evaluate(np.concatenate([idx - h, idx, idx + h]))[0].reshape(3, len(idx), 4)
    return (p[2] - p[0]) / (2 * h * DT), (p[2] - 2 * p[1] + p[0]) / (h * DT) ** 2


def test_a_swing_from_rest_is_the_minimum_jerk_blend_and_the_height_sextic():
    sw = _swing()
    idx = np.arange(10, 211)
    pos = sw.evaluate(idx)[0]
    u = (idx - 10) / 200
    np.testing.assert_allclose(pos[:, :3], swing_path(sw.start[:3], sw.end[:3], 0.08, u), atol=1e-12)
    np.testing.assert_allclose(pos[:, 3], 0.3 * min_jerk(u), atol=1e-12)
    np.testing.assert_allclose(pos[100, 2], 0.05 + 0.08, atol=1e-12)  # the apex at mid-swing


def test_rates_and_accelerations_are_the_derivatives_of_the_positions():
    sw = _swing()
    idx = np.arange(12, 208, 7)
    _, vel, acc = sw.evaluate(idx)
    fd1, fd2 = _finite_differences(sw, idx)
    np.testing.assert_allclose(vel, fd1, atol=1e-6)
    np.testing.assert_allclose(acc, fd2, atol=1e-4)


@pytest.mark.parametrize("i_land", [210, 250, 190])
@pytest.mark.parametrize("z1", [0.05, 0.0])
def test_a_retarget_mid_swing_is_continuous_in_position_velocity_and_acceleration(i_land, z1):
    sw, i, h = _swing(), 80, 1e-3
    old = copy.deepcopy(sw)
    target = np.array([0.55, 0.02, z1, -0.2])
    sw.retarget(i, target, i_land)
    for b, a in zip(old.evaluate(np.array([i])), sw.evaluate(np.array([i])), strict=True):
        np.testing.assert_allclose(a, b, atol=1e-9)  # the analytic state at i is kept
    # one-sided differences of the positions (the old swing before i, the new one after) agree
    p = np.concatenate([old.evaluate(i - h * np.arange(2, 0, -1))[0], sw.evaluate(i + h * np.arange(3))[0]])
    v = np.diff(p, axis=0) / (h * DT)
    a = np.diff(v, axis=0) / (h * DT)
    np.testing.assert_allclose(v[1], v[2], atol=1e-3)  # velocity: no jump
    np.testing.assert_allclose(a[1], a[0], atol=0.05)  # acceleration: no jump
    np.testing.assert_allclose(a[1], a[2], atol=0.05)
    # lands at rest on the target at the new touchdown
    pos, vel, acc = sw.evaluate(np.array([i_land - 1e-9, i_land]))
    np.testing.assert_allclose(pos[0], target, atol=1e-9)
    np.testing.assert_allclose(vel[0], 0.0, atol=1e-6)
    np.testing.assert_allclose(acc[0], 0.0, atol=1e-3)
    np.testing.assert_array_equal(pos[1], target)
    if i_land != 210 or z1 != 0.05:  # the height restarted: through the apex at the new mid-swing
        mid = 0.5 * (10 + i_land)
        np.testing.assert_allclose(sw.evaluate(np.array([mid]))[0][0, 2], max(0.0, z1) + 0.08, atol=1e-12)


def test_a_retarget_with_the_touchdown_kept_keeps_the_height_sextic():
    sw, ref = _swing(), _swing()
    sw.retarget(80, np.array([0.55, 0.02, 0.05, -0.2]))
    idx = np.arange(10, 211)
    np.testing.assert_array_equal(sw.evaluate(idx)[0][:, 2], ref.evaluate(idx)[0][:, 2])


def test_the_height_past_its_apex_time_is_the_quintic_from_the_current_state():
    coef = height_from_state(0.1, -0.2, -1.0, 0.0, 0.3, 0.13, -0.1)
    assert coef[6] == 0.0
    z = np.polynomial.polynomial.Polynomial(coef)
    L = 0.3
    np.testing.assert_allclose([z(0), z.deriv()(0) / L, z.deriv(2)(0) / L**2], [0.1, -0.2, -1.0], atol=1e-12)
    np.testing.assert_allclose([z(1), z.deriv()(1), z.deriv(2)(1)], [0.0, 0.0, 0.0], atol=1e-12)


def test_a_foot_track_rests_before_lift_off_and_on_the_target_after_touchdown():
    track = FootTrack(np.array([0.0, 0.1, 0.0, 0.0]))
    track.swings.append(_swing())
    pos, vel, _ = track.evaluate(0, 300)
    np.testing.assert_array_equal(pos[:11], np.broadcast_to(track.rest, (11, 4)))
    np.testing.assert_array_equal(pos[210:], np.broadcast_to(track.swings[0].end, (90, 4)))
    assert np.all(vel[:11] == 0) and np.all(vel[210:] == 0) and track.active(100) is track.swings[0]
    track.prune(210)
    assert not track.swings and track.rest[0] == 0.4
