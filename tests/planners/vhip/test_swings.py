"""Swing feet of the streaming generator: the precomputed swing path equals the minimum-jerk/sextic
swing of gait.swing, feet rest where they landed, and a redirected swing continues from where the
foot is.

Oracle: :func:`gaitshift.gait.swing.swing_path` evaluated per sample (a separate implementation that
builds the sextic per sample instead of reusing a basis).
"""

import numpy as np

from gaitshift.gait.swing import swing_path
from gaitshift.planners.vhip.swings import FootTracks


def _tracks():
    return FootTracks({0: np.array([0.0, 0.1, 0.0]), 1: np.array([0.0, -0.1, 0.0])}, clearance=0.08)


def test_swing_path_equals_the_minimum_jerk_sextic_swing():
    tracks = _tracks()
    start, end = np.array([0.0, 0.1, 0.0]), np.array([0.5, 0.12, 0.05])
    sw = tracks.path(10, 110, start, end)
    u = np.arange(100) / 100
    np.testing.assert_allclose(sw.path, swing_path(start, end, 0.08, u), atol=1e-12)
    again = tracks.path(300, 400, end, start)  # same length: the cached basis, other end points
    np.testing.assert_allclose(again.path, swing_path(end, start, 0.08, u), atol=1e-12)


def test_feet_rest_before_lift_off_and_after_touchdown():
    tracks = _tracks()
    end = np.array([0.4, 0.1, 0.0])
    tracks.set_lift(0, 20, tracks.home[0])
    tracks.swing_to(0, 60, end)
    pos = tracks.positions(0, np.arange(0, 100))
    np.testing.assert_array_equal(pos[:20], np.broadcast_to(tracks.home[0], (20, 3)))
    np.testing.assert_array_equal(pos[60:], np.broadcast_to(end, (40, 3)))
    assert np.all(pos[21:60, 2] > 0)
    np.testing.assert_array_equal(tracks.positions(1, np.arange(5, 9)), np.broadcast_to(tracks.home[1], (4, 3)))
    tracks.prune(61)
    assert not tracks.swings[0] and np.array_equal(tracks.home[0], end)


def test_a_redirected_swing_continues_from_the_current_foot_position():
    tracks = _tracks()
    tracks.set_lift(1, 0, tracks.home[1])
    tracks.swing_to(1, 100, np.array([0.5, -0.1, 0.0]))
    now = 40
    here = tracks.positions(1, np.array([now]))[0]
    tracks.redirect(1, now, 120, np.array([0.6, -0.15, 0.0]))
    after = tracks.positions(1, np.arange(now, 121))
    np.testing.assert_array_equal(after[0], here)
    np.testing.assert_allclose(after[-1], [0.6, -0.15, 0.0])
    assert tracks.swings[1][-1].i0 == now
