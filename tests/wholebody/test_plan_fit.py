"""The pieces of the plan-fit check (gaitshift.wholebody.plan_fit, ik_tasks.trailing_soles), against
closed forms:

* the trailing sole of a double support is the one that lifts off next, and no sole of a single
  support or a flight is one;
* the toe-off check refuses a ZMP outside the support a pivoting sole leaves, and the ground check a
  sole in contact below the ground, each as one (time, check, cause).
"""

from __future__ import annotations

import numpy as np

from gaitshift.wholebody.ik_tasks import trailing_soles
from gaitshift.wholebody.plan_fit import PlanFit, fit_violation


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
