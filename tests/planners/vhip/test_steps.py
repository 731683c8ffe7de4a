"""The step planner writes each running step so that eq. (9') holds with the planned foothold, keeps
the lateral oscillation, and re-plans the next step from a measured state through eq. (9').

Oracles: the rows of eq. (9') and the row weights w = (z'' + g) dt^2 / z evaluated here from the
planned samples; the take-off velocity from the CoM differences.
"""

import numpy as np

import gaitshift
from gaitshift.planners.vhip.horizons import VhipHorizons
from gaitshift.planners.vhip.steps import StepPlanner

G = 9.81


def _planner():
    sc = gaitshift.load_scenario({"planner": "vhip", "dt": 0.004})
    h = VhipHorizons.from_scenario(sc)
    return StepPlanner(sc, h, []), h


def _rows(p, a, b):
    """Residuals of eq. (9') at samples a+1..b-1 of the plan buffer (no solve)."""
    c, z, zdd, zmp = (p.buf[k][a : b + 1] for k in ("c", "z", "zdd", "zmp"))
    f = zdd + G
    w = np.where(f > 1e-9 * G, f * p.h.dt**2 / z, 0.0)[1:-1, None]
    return -c[:-2] + (2 + w) * c[1:-1] - c[2:] - w * np.nan_to_num(zmp[1:-1])


def test_each_running_step_satisfies_eq9_with_its_foothold():
    p, h = _planner()
    first = p.start(0.0, np.array([0.3, 0.0]))
    assert first == h.n_start + h.n_sup and len(p.takeoffs) == 2
    for _ in range(3):
        p.run_step(0.0, np.array([0.6, 0.0]))
    assert len(p.takeoffs) == 5 and p.buf.n == first + 4 * h.n_step + 1
    for k in range(1, 5):
        a, b = p.takeoffs[k - 1].index, p.takeoffs[k].index
        assert np.max(np.abs(_rows(p, a, b))) < 1e-12
        v = (p.buf["c"][b] - p.buf["c"][b - 1]) / h.dt
        np.testing.assert_allclose(v, p.takeoffs[k].target, atol=1e-9)
    targets = np.array([tk.target for tk in p.takeoffs])
    np.testing.assert_allclose(targets[1:, 0], [0.3, 0.6, 0.6, 0.6], atol=1e-12)  # <= 0.3 m/s change per step
    np.testing.assert_allclose(np.abs(targets[:, 1]), abs(h.u_left), atol=1e-12)  # the oscillation alone
    assert p.events == []  # every change within the limits: nothing clamped


def test_replan_propagates_the_measured_state_and_keeps_the_take_off_target():
    p, h = _planner()
    p.start(0.0, np.array([0.3, 0.0]))
    p.run_step(0.0, np.array([0.3, 0.0]))
    i, j = p.takeoffs[1].index + 10, p.takeoffs[2].index
    pos, vel = p.buf["c"][i] + [0.01, 0.0], np.array([0.35, 0.05])
    offset, shift = p.replan(1.0, pos, vel, i, j)
    assert abs(offset - 0.01) < 1e-12 and shift > 0
    np.testing.assert_allclose(p.buf["c"][i], pos, atol=1e-15)
    np.testing.assert_allclose((p.buf["c"][i + 1] - p.buf["c"][i]) / h.dt, vel, atol=1e-9)
    assert np.max(np.abs(_rows(p, i, j))) < 1e-12
    assert np.max(np.abs(_rows(p, j, p.takeoffs[-1].index))) < 1e-12
