"""Stiffness values of paper 001 §III are exact roots of the closed-form boundary conditions.

The oracle here is code written independently of gaitshift: scalar closed forms of eq. (1) with a
constant ZMP, and numerical ODE integration (scipy solve_ivp).
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import gaitshift
from gaitshift.errors import InputError, StiffnessError
from gaitshift.models.stiffness import (
    running_residual,
    solve_running,
    solve_transition,
    sweep_running,
    transition_residual,
)

G = 9.81
GRID = np.round(np.arange(0.10, 0.395, 0.01), 2)


def support_z(z0, v0, T, t, g=G):
    """Vertical LIPM z'' = z/T^2 - g from (z0, v0), written out by hand."""
    w = 1.0 / T
    zs = g * T * T
    return (
        zs + (z0 - zs) * math.cosh(w * t) + v0 / w * math.sinh(w * t),
        (z0 - zs) * w * math.sinh(w * t) + v0 * math.cosh(w * t),
    )


def test_walking_stiffness_is_sqrt_h_over_g():
    k = gaitshift.stiffness(0.95, 0.4, 0.15, 0.15)
    assert k.T_w == pytest.approx(math.sqrt(0.95 / 9.81), abs=1e-15)


def test_running_root_is_exact_on_the_900_point_grid():
    S, F = np.meshgrid(GRID, GRID, indexing="ij")
    Tr, vr, _, _ = sweep_running(0.95, S, F)
    assert Tr.shape == (30, 30)
    worst = 0.0
    for T, v, tss, tf in zip(Tr.ravel(), vr.ravel(), S.ravel(), F.ravel(), strict=True):
        z1, v1 = support_z(0.95, v, T, tss)
        z2, v2 = z1 + v1 * tf - 0.5 * G * tf**2, v1 - G * tf
        worst = max(worst, abs(z2 - 0.95), abs(v2 - v))
    assert worst < 1e-10
    # v_r = -g tau_F / 2 by time symmetry of the stance phase (independent of T)
    np.testing.assert_allclose(vr, -0.5 * G * F, atol=1e-10)
    # T_r lies below T_w and decreases with flight, increases with stance (Fig. 7 discussion)
    assert np.all(Tr < math.sqrt(0.95 / G))
    assert np.all(np.diff(Tr, axis=1) < 0) and np.all(np.diff(Tr, axis=0) > 0)


@pytest.mark.parametrize("tds", [0.15, 0.20])
def test_transition_root_is_exact_on_the_grid(tds):
    S, F = np.meshgrid(GRID, GRID, indexing="ij")
    Tr, vr, _, _ = solve_running(0.95, S, F)
    T0, T1, _, _ = solve_transition(0.95, tds, S, vr, T_guess=Tr)
    worst = 0.0
    for a, b, tss, v in zip(T0.ravel(), T1.ravel(), S.ravel(), vr.ravel(), strict=True):
        z1, v1 = support_z(0.95, 0.0, a, tds)
        z2, v2 = support_z(z1, v1, b, tss)
        worst = max(worst, abs(z2 - 0.95), abs(v2 + v))
    assert worst < 1e-10


def test_stiffness_matches_numerical_integration_of_eq1():
    h, tss, tds, tf = 0.95, 0.4, 0.15, 0.15
    k = gaitshift.stiffness(h, tss, tds, tf)

    def rhs(T):
        return lambda t, y: [y[1], y[0] / T**2 - G]

    # running half cycle: SS then ballistic flight returns to (h, v_r)
    s = solve_ivp(rhs(k.T_r), (0, tss), [h, k.v_r], rtol=1e-12, atol=1e-13).y[:, -1]
    z2, v2 = s[0] + s[1] * tf - 0.5 * G * tf**2, s[1] - G * tf
    assert abs(z2 - h) < 1e-9 and abs(v2 - k.v_r) < 1e-9
    # transition: DS(T_t0) then SS(T_t1) from rest reaches the take-off state (h, -v_r)
    s = solve_ivp(rhs(k.T_t0), (0, tds), [h, 0.0], rtol=1e-12, atol=1e-13).y[:, -1]
    s = solve_ivp(rhs(k.T_t1), (0, tss), s, rtol=1e-12, atol=1e-13).y[:, -1]
    assert abs(s[0] - h) < 1e-9 and abs(s[1] + k.v_r) < 1e-9


@pytest.mark.parametrize("which", ["running", "transition"])
def test_analytic_jacobian_matches_finite_differences(which):
    x = np.array([0.27, -0.5]) if which == "running" else np.array([0.38, 0.26])

    def f(x):
        if which == "running":
            return running_residual(x[0], x[1], 0.95, 0.4, 0.15)
        return transition_residual(x[0], x[1], 0.95, 0.15, 0.4, -0.73575)

    _, J = f(x)
    eps = 1e-7
    num = np.column_stack([(f(x + eps * e)[0] - f(x - eps * e)[0]) / (2 * eps) for e in np.eye(2)])
    np.testing.assert_allclose(J, num, rtol=1e-6, atol=1e-8)


def test_no_transition_root_raises_stiffness_error():
    # tau_DS too short: even free fall in double support cannot build the speed the take-off needs
    with pytest.raises(StiffnessError, match="double_support"):
        gaitshift.stiffness(0.95, 0.4, 0.05, 0.15)


@pytest.mark.parametrize(
    "bad",
    [
        {"height": 0.0},
        {"height": -1.0},
        {"flight": float("nan")},
        {"single_support": -0.1},
        {"double_support": float("inf")},
    ],
)
def test_non_positive_or_nan_inputs_are_rejected(bad):
    args = {"height": 0.95, "single_support": 0.4, "double_support": 0.15, "flight": 0.15} | bad
    with pytest.raises(InputError, match=next(iter(bad))):
        gaitshift.stiffness(**args)
