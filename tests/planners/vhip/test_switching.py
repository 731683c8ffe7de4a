"""Start and stop (State Switching 1 and 3): the segmented cubic ZMP problem of eqs. (15)-(18).

Oracles: Hermite end conditions, numerical quadrature of the smoothness objective and an independent
dense solve of eq. (13) for the CoM of the returned ZMP (the IPOPT reference: test_switching_ipopt.py).
"""

from __future__ import annotations

import numpy as np
import pytest
from switching_cases import DT, N_DS, N_FLY, N_SUP, G, dense_com, start_problem, vertical

from gaitshift.errors import InfeasibleError
from gaitshift.models.vhip import row_weights
from gaitshift.planners.vhip.switching import (
    SwitchingSolver,
    hermite_coefficients,
    smoothness,
    solve_stop,
    solve_switching,
    stop_problem,
)


def test_corrected_eq18_meets_the_hermite_end_conditions():
    dT, x0, xd0, x1, xd1 = 0.6, 0.0, 0.0, 0.1, 0.2
    b = hermite_coefficients(dT, x0, xd0, x1, xd1)
    poly = np.polynomial.Polynomial(b)
    assert poly(0) == pytest.approx(x0) and poly.deriv()(0) == pytest.approx(xd0)
    assert poly(dT) == pytest.approx(x1) and poly.deriv()(dT) == pytest.approx(xd1)
    # the printed b_2 (2 dT xd1 instead of dT xd1) misses the end point
    b_printed = b.copy()
    b_printed[2] = -(3 * x0 + 2 * dT * xd0 - 3 * x1 + 2 * dT * xd1) / dT**2
    assert abs(np.polynomial.Polynomial(b_printed)(dT) - x1) > 1e-2


def test_smoothness_closed_form_matches_quadrature():
    h1, h2, y0, ym, ydm, y1 = 0.45, 0.75, 0.0, -0.02, 0.05, 0.1
    t = np.linspace(0, h1 + h2, 200001)
    b1 = np.polynomial.Polynomial(hermite_coefficients(h1, y0, 0.0, ym, ydm))
    b2 = np.polynomial.Polynomial(hermite_coefficients(h2, ym, ydm, y1, 0.0))
    ydd = np.where(t <= h1, b1.deriv(2)(t), b2.deriv(2)(t - h1))
    assert smoothness(h1, h2, y0, ym, ydm, y1) == pytest.approx(np.trapezoid(ydd**2, t), rel=1e-4)


def test_start_solution_meets_every_constraint_of_eq16():
    prob = start_problem()
    sol = solve_switching(prob)
    T = N_DS * DT
    # (16d): both segments positive, summing to T
    assert np.all(sol.dT1 > 0) and np.all(sol.dT1 < T)
    # (15): ZMP end values and zero end rates (finite differences of the sampled ZMP)
    np.testing.assert_allclose(sol.zmp[0], prob.y0, atol=1e-12)
    np.testing.assert_allclose(sol.zmp[-1], prob.y1, atol=1e-12)
    z = sol.zmp  # second-order one-sided differences: O(dt^2) for a cubic
    assert np.all(np.abs(-3 * z[0] + 4 * z[1] - z[2]) / (2 * DT) < 1e-4)
    assert np.all(np.abs(3 * z[-1] - 4 * z[-2] + z[-3]) / (2 * DT) < 1e-4)
    # (16g): ZMP inside the double-support polygon
    assert np.all(sol.zmp >= prob.lo - 1e-12) and np.all(sol.zmp <= prob.hi + 1e-12)
    # (16e)-(16f) by an independent dense solve of eq. (13)
    p = np.vstack([sol.zmp, np.repeat(prob.y1[None], len(prob.w) - N_DS - 1, 0)])
    c = dense_com(prob.w, p, np.zeros(2), prob.v_end, DT)
    np.testing.assert_allclose(c[0], prob.c0, atol=1e-9)
    np.testing.assert_allclose((c[-1] - c[-2]) / DT, prob.v_end, atol=1e-9)
    np.testing.assert_allclose(sol.com, c, atol=1e-9)


def test_stop_ends_at_rest_over_the_midpoint_of_the_feet():
    vg = vertical()
    z, _, zdd = vg.stop_horizon(DT, N_FLY, N_SUP, N_DS)
    w = row_weights(z, zdd, G, DT)
    v_start = np.array([0.05, 0.2])
    offset = np.array([0.0, -0.2])
    lo, hi = np.array([-0.1, -0.26]), np.array([0.1, 0.06])
    _, com, zmp = solve_stop(stop_problem(w, N_DS, DT, v_start, offset, lo, hi))
    n = len(w) - 1
    p = np.zeros((n + 1, 2))
    p[n - N_DS :] = zmp
    c = dense_com(w, p, v_start, np.zeros(2), DT)  # forward time, independent solve
    np.testing.assert_allclose(com, c - c[0] + com[0], atol=1e-9)
    np.testing.assert_allclose(c[-1] - c[0] + com[0], offset / 2, atol=1e-9)  # at rest over the midpoint
    np.testing.assert_allclose((com[1] - com[0]) / DT, v_start, atol=1e-9)
    np.testing.assert_allclose((com[-1] - com[-2]) / DT, 0.0, atol=1e-9)
    np.testing.assert_allclose(zmp[-1], offset / 2, atol=1e-12)
    assert np.all(zmp >= lo - 1e-12) and np.all(zmp <= hi + 1e-12)
    # reusing a prepared solver gives the same answer
    prob = stop_problem(w, N_DS, DT, v_start, offset, lo, hi)
    again = SwitchingSolver(prob.w, N_DS, DT).solve(prob)
    np.testing.assert_allclose(again.com[::-1], com, atol=1e-12)


def test_unreachable_start_speed_is_infeasible():
    with pytest.raises(InfeasibleError, match="support polygon"):
        solve_switching(start_problem(v_end=(50.0, -0.2)))
