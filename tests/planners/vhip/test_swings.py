"""Swing feet of the VHIP generator on the shared tracker: a swing from rest is the minimum-jerk blend
and height sextic of gait.swing, feet rest where they landed, and a redirected swing (in the tracks and
in a re-planned run of the generator) continues from the foot's current position, velocity and
acceleration: no kink in the reference at the redirect.

Oracles: :func:`gaitshift.gait.swing.swing_path` (a separate evaluation of the paper 003 swing) and
finite differences of the sampled foot positions.
"""

import numpy as np

import gaitshift
from gaitshift.gait.swing import min_jerk, swing_path
from gaitshift.planners.vhip.generator import VhipGenerator
from gaitshift.planners.vhip.swings import FootTracks

DT = 0.001


def _tracks():
    return FootTracks({0: np.array([0.0, 0.1, 0.0]), 1: np.array([0.0, -0.1, 0.0])}, clearance=0.08, dt=DT)


def test_a_swing_from_rest_is_the_minimum_jerk_sextic_swing():
    tracks = _tracks()
    start, end = np.array([0.0, 0.1, 0.0]), np.array([0.5, 0.12, 0.05])
    tracks.set_lift(0, 10, start)
    tracks.swing_to(0, 110, end)
    pos = tracks.positions(0, np.arange(10, 110))
    u = np.arange(100) / 100
    np.testing.assert_allclose(pos, swing_path(start, end, 0.08, u), atol=1e-12)
    np.testing.assert_allclose(pos[:, :2], start[:2] + (end - start)[:2] * min_jerk(u)[:, None], atol=1e-12)


def test_feet_rest_before_lift_off_and_after_touchdown():
    tracks = _tracks()
    end = np.array([0.4, 0.1, 0.0])
    tracks.set_lift(0, 20, tracks.home[0])
    tracks.swing_to(0, 60, end)
    pos = tracks.positions(0, np.arange(0, 100))
    np.testing.assert_array_equal(pos[:20], np.broadcast_to([0.0, 0.1, 0.0], (20, 3)))
    np.testing.assert_array_equal(pos[60:], np.broadcast_to(end, (40, 3)))
    assert np.all(pos[21:60, 2] > 0)
    np.testing.assert_array_equal(tracks.positions(1, np.arange(5, 9)), np.broadcast_to(tracks.home[1], (4, 3)))
    tracks.prune(61)
    assert not tracks.tracks[0].swings and np.array_equal(tracks.home[0], end)


def _jumps(pos, i):
    """Velocity and acceleration jumps (m/s, m/s^2) of sampled positions (n, 3) at sample ``i``,
    each against the largest change of the same difference elsewhere in ``pos``."""
    v = np.diff(pos, axis=0) / DT  # v[k]: between samples k and k+1
    a = np.diff(v, axis=0) / DT  # a[k]: centred on sample k+1
    dv, da = np.abs(np.diff(v, axis=0)).max(axis=1), np.abs(np.diff(a, axis=0)).max(axis=1)
    at = slice(i - 2, i + 1)  # differences that straddle sample i
    rest = np.ones(len(dv), bool)
    rest[at] = False
    return dv[at].max(), dv[rest].max(), da[at].max(), da[rest[:-1]].max()


def test_a_redirected_swing_is_continuous_in_position_velocity_and_acceleration():
    tracks = _tracks()
    tracks.set_lift(1, 0, tracks.home[1])
    tracks.swing_to(1, 100, np.array([0.5, -0.1, 0.0]))
    now = 40
    before = tracks.positions(1, np.arange(0, now + 1))
    tracks.redirect(1, now, 100, np.array([0.6, -0.25, 0.0]))
    after = tracks.positions(1, np.arange(now, 101))
    np.testing.assert_allclose(after[0], before[-1], rtol=0, atol=1e-15)
    np.testing.assert_allclose(after[-1], [0.6, -0.25, 0.0])
    dv, dv_else, da, da_else = _jumps(np.concatenate([before[:-1], after]), now)
    assert dv <= dv_else and da <= 1.5 * da_else  # no kink: the changes across the redirect are ordinary


def test_a_replanned_run_redirects_the_swing_foot_without_a_kink():
    """A lateral shove mid-swing while running: the re-planned foothold moves, the foot in the air
    turns towards it smoothly (its sampled velocity and acceleration do not jump)."""
    gen = VhipGenerator(gaitshift.load_scenario("paper003-variable-speed"))
    gen.command(0.3, 0.0)
    for _ in range(6):
        gen.step()
    blocks = [gen.advance(40)]
    now = gen.tick_index
    assert blocks[0].t[-1] == (now - 1) * DT
    gen.replan(gen.planned_com(now), np.array([0.3, 0.15]))
    assert gen.events[-1].kind == "replan" and gen.events[-1].applied > 0.01  # the foothold moved
    blocks.append(gen.step())
    pos = np.concatenate([b.foot_pos for b in blocks])
    k = len(blocks[0].t)  # the redirect (sample now), in the samples of pos
    in_air = np.flatnonzero(~np.concatenate([b.contact for b in blocks])[k])
    assert len(in_air) > 0
    for side in in_air:  # a flight: the redirected foot and the one that just took off
        dv, dv_else, da, da_else = _jumps(pos[:, side], k)
        assert dv <= dv_else and da <= 1.5 * da_else
