"""Start and stop segments of a VHIP run (State Switching 1 and 3): the start reaches the wanted
take-off velocity or the fastest feasible fraction of it, the stop ends at rest over the midpoint of
the last two feet, and the ZMP stays in the feet.

Oracles: the segment's own samples re-checked here (finite differences of the CoM, the ZMP against
the support boxes built from the feet), no solver output used as reference.
"""

import numpy as np

import gaitshift
from gaitshift.planners.vhip.horizons import VhipHorizons
from gaitshift.planners.vhip.transitions import solve_start, solve_stop
from gaitshift.trajectory.contract import DS, FLIGHT, LEFT


def _horizons():
    return VhipHorizons.from_scenario(gaitshift.load_scenario({"planner": "vhip", "dt": 0.004}))


def test_start_reaches_the_wanted_take_off_velocity():
    h = _horizons()
    y1 = np.array([0.0, 0.5 * h.width])
    seg = solve_start(h, np.array([0.3, 0.0]), LEFT, y1)
    assert seg.scale == 1.0
    n = h.n_start + h.n_sup
    assert len(seg.com) == len(seg.phase) == n + 1
    v_end = (seg.com[-1] - seg.com[-2]) / h.dt
    np.testing.assert_allclose(v_end, [0.3, h.oscillation(LEFT)], atol=1e-9)
    np.testing.assert_allclose(seg.com[1] - seg.com[0], 0.0, atol=1e-12)  # from rest
    ds = seg.phase == DS
    half = h.zmp_half
    assert np.all(np.abs(seg.zmp[ds, 0]) <= half[0] + 1e-12)
    assert np.all(np.abs(seg.zmp[ds, 1]) <= 0.5 * h.width + half[1] + 1e-12)
    assert np.all(np.isnan(seg.zmp[seg.phase == FLIGHT]))


def test_an_unreachable_start_gives_the_fastest_feasible_fraction():
    h = _horizons()
    y1 = np.array([0.0, 0.5 * h.width])
    seg = solve_start(h, np.array([40.0, 0.0]), LEFT, y1)
    assert 0.0 < seg.scale < 1.0
    v_end = (seg.com[-1] - seg.com[-2]) / h.dt
    np.testing.assert_allclose(v_end[0], 40.0 * seg.scale, atol=1e-9)
    # a little faster is infeasible: the bound is active on the x axis
    assert np.max(np.abs(seg.zmp[seg.phase == DS, 0])) > h.zmp_half[0] - 1e-3


def test_stop_ends_at_rest_over_the_midpoint_of_the_last_two_feet():
    h = _horizons()
    c_prev, v_prev = np.array([3.0, 0.05]), np.array([0.0, h.oscillation(LEFT)])
    seg = solve_stop(h, 1 - LEFT, c_prev, v_prev)
    np.testing.assert_allclose(seg.com[0], c_prev, atol=1e-12)
    np.testing.assert_allclose((seg.com[1] - seg.com[0]) / h.dt, v_prev, atol=1e-9)
    np.testing.assert_allclose(seg.com[-1], 0.5 * (seg.A + seg.B), atol=1e-9)
    np.testing.assert_allclose(seg.com[-1] - seg.com[-2], 0.0, atol=1e-12)
    np.testing.assert_allclose(np.abs(seg.B - seg.A), [0.0, h.width], atol=1e-12)
    assert np.all(seg.phase[seg.n_ss_end :] == DS)
