"""The legs' clearance, the truth the step limits are checked against: MuJoCo contacts between the two
legs' collision geoms, and the two feet's footprints passing through each other (which the G1's
sphere soles do not collide). Oracles: a dense point sampling of the rectangles for the
separating-axis test, and poses whose geometry is known (standing apart, legs crossed)."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from gaitshift.robots.model import standing_qpos
from gaitshift.sim.leg_clearance import LegClearance, footprints_overlap
from gaitshift.sim.plant import build_plant


@pytest.fixture(scope="module")
def g1():
    return build_plant()


def _frames(plant, d):
    return [plant.sole_frame(d, s) for s in (0, 1)]


def _sampled_overlap(centres, axes, half, n=81):
    """Brute force: does a grid point of either rectangle lie inside the other?"""
    u = np.linspace(-1.0, 1.0, n)
    grid = np.stack(np.meshgrid(u * half[0], u * half[1]), -1).reshape(-1, 2)
    frames = [np.array([a, [-a[1], a[0]]]) for a in axes]
    for i, j in ((0, 1), (1, 0)):
        pts = centres[i] + grid @ frames[i]
        local = (pts - centres[j]) @ frames[j].T
        if np.any(np.all(np.abs(local) <= half, axis=1)):
            return True
    return False


def test_the_footprint_overlap_is_the_separating_axis_test_of_the_two_rectangles():
    rng = np.random.default_rng(3)
    half = np.array([0.09, 0.035])
    seen = {True: 0, False: 0}
    for _ in range(400):
        centres = rng.uniform(-0.15, 0.15, (2, 2))
        ang = rng.uniform(-np.pi, np.pi, 2)
        axes = np.stack([np.cos(ang), np.sin(ang)], 1)
        got = footprints_overlap(centres, axes, half)
        # skip the grazing cases the grid cannot resolve: the answer must not flip within 3 mm
        nudges = 3e-3 * np.array([[1, 0], [-1, 0], [0, 1], [0, -1]])
        answers = {footprints_overlap(centres + np.array([np.zeros(2), n]), axes, half) for n in nudges}
        if answers != {got}:
            continue
        assert got == _sampled_overlap(centres, axes, half), (centres, ang)
        seen[got] += 1
    assert min(seen.values()) > 50  # both answers were tested


def test_standing_feet_are_clear_and_crossed_legs_touch_and_overlap(g1):
    m = g1.model
    lc = LegClearance.of(g1)
    left, right = (frozenset(np.flatnonzero(lc.leg_of == s)) for s in (0, 1))
    assert {m.body(b).name for b in left} >= {"left_hip_pitch_link", "left_knee_link", "left_ankle_roll_link"}
    assert {m.body(b).name for b in right} >= {"right_hip_pitch_link", "right_knee_link", "right_ankle_roll_link"}
    assert "pelvis" not in {m.body(b).name for b in left | right}
    d = mujoco.MjData(m)
    d.qpos[:] = standing_qpos(g1)
    mujoco.mj_forward(m, d)
    assert lc.read(d, _frames(g1, d)).tolist() == [False, False]
    # adduct both hips: the legs swing into each other and the feet cross
    for name, sign in (("left_hip_roll_joint", -1.0), ("right_hip_roll_joint", 1.0)):
        d.qpos[m.joint(name).qposadr[0]] = sign * 0.35
    mujoco.mj_forward(m, d)
    assert lc.legs_touch(d)
    assert lc.feet_overlap(_frames(g1, d))
    # the same feet, one lifted above the other foot's depth: not overlapping any more
    left_ankle = m.joint("left_hip_pitch_joint").qposadr[0]
    d.qpos[left_ankle] = -1.2  # hip flexed: the left foot swings forward and up
    mujoco.mj_forward(m, d)
    assert not lc.feet_overlap(_frames(g1, d))
