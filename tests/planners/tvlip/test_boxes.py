"""The ZMP boxes of eq. (7) (paper 001): the stance sole next to a single support, the rectangle over
both soles between two double supports, and the landing box in front of a truncated flight.

Oracles: the soles rebuilt here from the footsteps' position and yaw (rotation matrices by hand).
"""

import math

import numpy as np

import gaitshift
from gaitshift.planners.tvlip.boxes import boxes_from_flight, build_boxes
from gaitshift.planners.tvlip.planner import sequence_for

SC = {
    "gait": [{"gait": "walk", "steps": 4}],
    "foot": {"size": [0.24, 0.14], "zmp_margin": 0.01, "zmp_z": [-0.02, 0.03]},
    "profile": {"max_stride": 0.3, "yaw_rate": 0.2, "step_height": 0.04, "accelerate_steps": 1, "decelerate_steps": 1},
}


def test_single_support_boundaries_get_the_stance_sole():
    sc = gaitshift.load_scenario(SC)
    seq, _ = sequence_for(sc)
    xy, z = build_boxes(seq, sc.foot.size, sc.foot.zmp_margin, sc.foot.zmp_z)
    half = np.array(sc.foot.size) / 2 - sc.foot.zmp_margin
    checked = 0
    for b in range(1, len(seq.phases)):
        ph = seq.phases[b - 1] if seq.phases[b - 1].kind == 1 else seq.phases[b] if seq.phases[b].kind == 1 else None
        if ph is None:
            continue
        foot = seq.footsteps[max(ph.on)]
        c, s = math.cos(foot.yaw), math.sin(foot.yaw)
        np.testing.assert_allclose(xy.origin[b], [foot.x, foot.y], atol=1e-12)
        np.testing.assert_allclose(xy.rot[b], [[c, -s], [s, c]], atol=1e-12)
        np.testing.assert_allclose(xy.hi[b], half, atol=1e-12)
        np.testing.assert_allclose(xy.lo[b], -half, atol=1e-12)
        assert z.origin[b, 0] == foot.z and z.lo[b, 0] == -0.02 and z.hi[b, 0] == 0.03
        checked += 1
    assert checked >= 8


def test_standing_boundaries_span_both_soles():
    sc = gaitshift.load_scenario(SC)
    seq, _ = sequence_for(sc)
    xy, _ = build_boxes(seq, sc.foot.size, sc.foot.zmp_margin, sc.foot.zmp_z)
    half = np.array(sc.foot.size) / 2 - sc.foot.zmp_margin
    width = sc.profile.step_width
    # boundary 0: standing on the initial feet (0, +/- w/2), yaw 0
    np.testing.assert_allclose(xy.origin[0], [0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(xy.hi[0], half + np.array([0.0, width / 2]), atol=1e-12)
    np.testing.assert_allclose(xy.rot[0], np.eye(2), atol=1e-12)
    # last boundary: the closing step stands beside the last foothold, same yaw
    a, b = seq.footsteps[-2], seq.footsteps[-1]
    np.testing.assert_allclose(xy.origin[-1], [(a.x + b.x) / 2, (a.y + b.y) / 2], atol=1e-12)
    np.testing.assert_allclose(xy.hi[-1], half + np.array([0.0, width / 2]), atol=1e-9)
    c, s = math.cos(a.yaw), math.sin(a.yaw)
    np.testing.assert_allclose(xy.rot[-1], [[c, -s], [s, c]], atol=1e-12)


def test_a_truncated_flight_gets_the_landing_box_in_front():
    sc = gaitshift.load_scenario("paper001-table2-walk-run-walk")
    seq, _ = sequence_for(sc)
    k = int(np.flatnonzero(seq.kind == 2)[0])
    sub = type(seq)(seq.phases[k:], seq.footsteps, seq.step_gait)
    xy, z = boxes_from_flight(sub, sc.foot.size, sc.foot.zmp_margin, sc.foot.zmp_z)
    rest, rest_z = build_boxes(type(seq)(seq.phases[k + 1 :], seq.footsteps, seq.step_gait), sc.foot.size, 0.0, (0, 0))
    assert len(xy.origin) == len(sub.phases) + 1
    np.testing.assert_array_equal(xy.origin[0], xy.origin[1])
    np.testing.assert_array_equal(xy.origin[1:], rest.origin)
    np.testing.assert_array_equal(z.origin[1:], rest_z.origin)
