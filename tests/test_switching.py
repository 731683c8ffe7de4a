"""Start and stop (State Switching 1 and 3): the segmented cubic ZMP problem of eqs. (15)-(18).

Oracles: Hermite end conditions, numerical quadrature of the smoothness objective, an independent
dense solve of eq. (13) for the CoM of the returned ZMP, and IPOPT solving the same problem.
"""

from __future__ import annotations

import numpy as np
import pytest

import gaitshift
from gaitshift.errors import InfeasibleError
from gaitshift.models.vhip import row_weights, stance_profiles, tridiagonal_system
from gaitshift.planners.switching import (SwitchingProblem, SwitchingSolver, hermite_coefficients,
                                          smoothness, solve_stop, solve_switching, stop_problem)

G, DT, N_DS, N_SUP, N_FLY = 9.81, 0.004, 300, 70, 30


def _vertical():
    sc = gaitshift.load_scenario("paper003-variable-speed")
    return stance_profiles(sc.heights, G, N_SUP * DT, N_FLY * DT)


def _start_problem(v_end=(0.3, -0.2), y1=(0.0, 0.1)):
    z, _, zdd = _vertical().start_horizon(DT, N_DS, N_SUP)
    w = row_weights(z, zdd, G, DT)
    return SwitchingProblem(w, N_DS, DT, np.zeros(2), np.array(y1), np.zeros(2), np.array(v_end),
                            np.array([-0.1, -0.15]), np.array([0.1, 0.15]))


def _dense_com(w, p, v0, v1, dt):
    lo, di, up = tridiagonal_system(w)
    A = np.diag(di) + np.diag(up, 1) + np.diag(lo, -1)
    rhs = w[:, None] * p
    rhs[0], rhs[-1] = np.asarray(v0) * dt, np.asarray(v1) * dt
    return np.linalg.solve(A, rhs)


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
    prob = _start_problem()
    sol = solve_switching(prob)
    T = N_DS * DT
    # (16d): both segments positive, summing to T
    assert np.all(sol.dT1 > 0) and np.all(sol.dT1 < T)
    # (15): ZMP end values and zero end rates (finite differences of the sampled ZMP)
    np.testing.assert_allclose(sol.zmp[0], prob.y0, atol=1e-12)
    np.testing.assert_allclose(sol.zmp[-1], prob.y1, atol=1e-12)
    z = sol.zmp   # second-order one-sided differences: O(dt^2) for a cubic
    assert np.all(np.abs(-3 * z[0] + 4 * z[1] - z[2]) / (2 * DT) < 1e-4)
    assert np.all(np.abs(3 * z[-1] - 4 * z[-2] + z[-3]) / (2 * DT) < 1e-4)
    # (16g): ZMP inside the double-support polygon
    assert np.all(sol.zmp >= prob.lo - 1e-12) and np.all(sol.zmp <= prob.hi + 1e-12)
    # (16e)-(16f) by an independent dense solve of eq. (13)
    p = np.vstack([sol.zmp, np.repeat(prob.y1[None], len(prob.w) - N_DS - 1, 0)])
    c = _dense_com(prob.w, p, np.zeros(2), prob.v_end, DT)
    np.testing.assert_allclose(c[0], prob.c0, atol=1e-9)
    np.testing.assert_allclose((c[-1] - c[-2]) / DT, prob.v_end, atol=1e-9)
    np.testing.assert_allclose(sol.com, c, atol=1e-9)


def test_ours_and_ipopt_solve_the_same_problem():
    pytest.importorskip("casadi")
    from gaitshift.planners.switching import solve_switching_ipopt

    prob = _start_problem()
    ours, ref = solve_switching(prob), solve_switching_ipopt(prob)
    for sol in (ours, ref):
        p = np.vstack([sol.zmp, np.repeat(prob.y1[None], len(prob.w) - N_DS - 1, 0)])
        c = _dense_com(prob.w, p, np.zeros(2), prob.v_end, DT)
        np.testing.assert_allclose(c[0], prob.c0, atol=1e-7)
        assert np.all(sol.zmp >= prob.lo - 1e-9) and np.all(sol.zmp <= prob.hi + 1e-9)
    # same optimum of the smoothness objective (ours scans dT1 on a 2 ms grid)
    np.testing.assert_allclose(ours.J, ref.J, rtol=1e-3, atol=1e-9)
    np.testing.assert_allclose(ours.dT1, ref.dT1, atol=0.01)


def test_stop_ends_at_rest_over_the_midpoint_of_the_feet():
    vg = _vertical()
    z, _, zdd = vg.stop_horizon(DT, N_FLY, N_SUP, N_DS)
    w = row_weights(z, zdd, G, DT)
    v_start = np.array([0.05, 0.2])
    offset = np.array([0.0, -0.2])
    lo, hi = np.array([-0.1, -0.26]), np.array([0.1, 0.06])
    sol, com, zmp = solve_stop(w, N_DS, DT, v_start, offset, lo, hi)
    n = len(w) - 1
    p = np.zeros((n + 1, 2))
    p[n - N_DS:] = zmp
    c = _dense_com(w, p, v_start, np.zeros(2), DT)   # forward time, independent solve
    np.testing.assert_allclose(com, c - c[0] + com[0], atol=1e-9)
    np.testing.assert_allclose(c[-1] - c[0] + com[0], offset / 2, atol=1e-9)   # at rest over the midpoint
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
        solve_switching(_start_problem(v_end=(50.0, -0.2)))
