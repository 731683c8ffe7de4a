"""The pieces of the plan-fit check (gaitshift.wholebody.plan_fit, ik_tasks.trailing_soles), against
closed forms:

* the trailing sole of a double support is the one that lifts off next, and no sole of a single
  support or a flight is one;
* the toe-off check refuses a ZMP outside the support a pivoting sole leaves, and the ground checks a
  sole in contact or a swing sole below the ground, each as one (time, check, cause);
* the margin that decides where a rear sole may pivot (``toe_off_margins``) is the plan's ZMP's distance
  inside the hull of its toe edge and the other sole: negative at its own centre, zero on the edge.
"""

from __future__ import annotations

from dataclasses import replace
from types import SimpleNamespace

import numpy as np

from gaitshift.wholebody.ik_tasks import trailing_soles
from gaitshift.wholebody.plan_fit import PlanFit, fit_violation, toe_off_margins


def test_the_trailing_sole_is_the_double_support_foot_that_lifts_next():
    # samples: DS, DS, SS(left), DS, DS, SS(right), flight, DS
    contact = np.array([[1, 1], [1, 1], [1, 0], [1, 1], [1, 1], [0, 1], [0, 0], [1, 1]], bool)
    expected = np.array([[0, 1], [0, 1], [0, 0], [1, 0], [1, 0], [0, 0], [0, 0], [0, 0]], bool)
    np.testing.assert_array_equal(trailing_soles(contact), expected)


def fit(zmp_margin: float | None, clearance: float) -> PlanFit:
    return PlanFit(1e-5, 1e-5, 3, 0.05, 0.004, zmp_margin, 2.0 if zmp_margin is not None else None, clearance, 3.0)


def test_the_checks_refuse_a_zmp_outside_the_toe_off_support_and_a_sole_below_the_ground():
    assert fit_violation(fit(0.001, -1e-4), 5e-4) is None
    assert fit_violation(fit(None, -4e-4), 5e-4) is None  # within the IK's position tolerance
    t, check, cause = fit_violation(fit(-0.002, 0.0), 5e-4)  # type: ignore[misc]
    assert (t, check) == (2.0, "toe-off support") and "2.0 mm outside" in cause
    t, check, cause = fit_violation(fit(0.01, -0.006), 5e-4)  # type: ignore[misc]
    assert (t, check) == (3.0, "ground") and "6.0 mm below" in cause


def test_the_swing_ground_check_refuses_a_swing_sole_corner_below_the_ground():
    ok = fit(None, 0.0)
    assert fit_violation(replace(ok, swing_clearance_m=-4e-4, swing_clearance_time_s=4.0), 5e-4) is None
    t, check, cause = fit_violation(replace(ok, swing_clearance_m=-0.0129, swing_clearance_time_s=3.61), 5e-4)  # type: ignore[misc]
    assert (t, check) == (3.61, "swing ground") and "a swing sole corner is 12.9 mm below" in cause


def test_the_toe_off_margin_is_the_zmps_distance_inside_the_toe_edge_and_the_other_sole():
    # soles side by side (y = +-0.1 m, flat, yaw 0), 0.18 x 0.07 m; the left one trails. The support of its
    # toe-off: the hull of its toe edge (x = 0.09, y in [0.065, 0.135]) and the right sole's rectangle.
    traj = SimpleNamespace(foot_pos=np.array([[[0.0, 0.1, 0.0], [0.0, -0.1, 0.0]]] * 3))
    traj.zmp = np.array([[0.0, 0.1, 0.0], [0.09, 0.1, 0.0], [0.0, -0.1, 0.0]])  # left centre, toe edge, right centre
    targets = np.broadcast_to(np.eye(3), (3, 2, 3, 3))
    trailing = np.array([[True, False]] * 3)
    margins = toe_off_margins(traj, targets, trailing, (0.18, 0.07))
    # behind the hull edge from (0.09, 0.135) to (-0.09, -0.065): 0.065 m in y times 0.18 / |(0.18, 0.2)|
    np.testing.assert_allclose(margins, [-0.065 * 0.18 / np.hypot(0.18, 0.2), 0.0, 0.035], atol=1e-9)
    assert np.all(np.isinf(toe_off_margins(traj, targets, ~trailing & False, (0.18, 0.07))))
