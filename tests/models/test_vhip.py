"""The VHIP model of paper 003 §2: vertical CoM (eqs. 3-6) and the tridiagonal ZMP<->CoM map (7-14).

Oracles: boundary conditions re-evaluated from independently built Vandermonde systems, a dense
linear solve, and eq. (2) recomputed from finite differences of the solved CoM.
"""

from __future__ import annotations

import numpy as np
import pytest

import gaitshift
from gaitshift.errors import InfeasibleError, ScenarioError
from gaitshift.models.sextic import sextic_eval
from gaitshift.models.tridiagonal import (
    Horizon,
    solve_banded_tridiagonal,
    solve_tridiagonal,
    thomas,
    tridiagonal_system,
)
from gaitshift.models.vhip import (
    flight_height,
    flight_takeoff_velocity,
    min_vertical_force,
    row_weights,
    stance_profiles,
)

G = 9.81


def test_flight_parabola_lands_at_touchdown_height_with_eq4_velocity():
    z_to, z_td, tf = 0.82, 0.78, 0.12
    zd_to, zd_td = flight_takeoff_velocity(z_to, z_td, tf, G)
    z, zd, zdd = flight_height(z_to, zd_to, np.array([0.0, tf]), G)
    assert z[1] == pytest.approx(z_td, abs=1e-12)
    assert zd[1] == pytest.approx(zd_td, abs=1e-12)
    assert np.all(zdd == -G)
    # equal heights: eq. (4), zd_to = g T_fly / 2 = -zd_td
    up, down = flight_takeoff_velocity(0.8, 0.8, tf, G)
    assert up == pytest.approx(G * tf / 2) and down == pytest.approx(-G * tf / 2)


def test_default_gait_never_pulls_on_the_ground():
    sc = gaitshift.load_scenario("paper003-variable-speed")
    vg = stance_profiles(sc.heights, G, 0.28, 0.12)
    for coef in (vg.start, vg.run, vg.stop):
        t = np.linspace(0, 0.28, 4001)[1:-1]
        _, _, zdd = sextic_eval(coef, t)
        assert np.all(zdd + G > 0)
        assert min_vertical_force(coef, 0.28, G)[0] > 0


def test_squat_that_needs_a_pulling_force_is_rejected_naming_z_low():
    with pytest.raises(InfeasibleError, match=r"heights\.z_low"):
        gaitshift.load_scenario({"planner": "vhip", "heights": {"z_low": 0.6}})


@pytest.mark.parametrize(
    "data, field",
    [
        ({"stance_ratio": 1.0}, "stance_ratio"),
        ({"stance_ratio": 0.0}, "stance_ratio"),
        ({"heights": {"z_low": 0.85}}, "heights.z_low"),
        ({"step_period": 0.4005}, "step_period"),
        ({"start_double_support": 0.0015}, "start_double_support"),
        ({"commands": [{"t": 0.0, "vx": float("nan")}]}, "commands.0.vx"),
        ({"commands": [{"t": 1.0}, {"t": 0.5}]}, "commands"),
    ],
)
def test_bad_scenarios_give_one_error_naming_the_field(data, field):
    with pytest.raises(ScenarioError) as err:
        gaitshift.load_scenario({"planner": "vhip", **data})
    msg = str(err.value)
    assert msg.startswith(field + " ") and "\n" not in msg


def _random_system(n, rng):
    w = rng.uniform(0, 2e-3, n + 1)
    w[rng.random(n + 1) < 0.3] = 0.0
    return w, rng.normal(size=n + 1)


def test_tridiagonal_solvers_agree_with_a_dense_solve():
    rng = np.random.default_rng(2)
    w, rhs = _random_system(60, rng)
    lo, di, up = tridiagonal_system(w)
    dense = np.diag(di) + np.diag(up, 1) + np.diag(lo, -1)
    ref = np.linalg.solve(dense, rhs)
    for x in (
        thomas(lo, di, up, rhs),
        solve_banded_tridiagonal(lo, di, up, rhs),
        solve_tridiagonal(lo, di, up, rhs),
        Horizon(w, 0.001).solve_rhs(rhs),
    ):
        np.testing.assert_allclose(x, ref, rtol=1e-9, atol=1e-9)
    # the adjoint solve
    np.testing.assert_allclose(
        Horizon(w, 0.001).solve_transposed(rhs), np.linalg.solve(dense.T, rhs), rtol=1e-9, atol=1e-9
    )


def test_solved_com_satisfies_eq2_and_the_velocity_rows():
    """Eq. (13) solved, then eq. (2) recomputed with (c_{i+1} - 2 c_i + c_{i-1})/dt^2 and z/(z''+g)."""
    dt = 0.002
    sc = gaitshift.load_scenario("paper003-variable-speed")
    vg = stance_profiles(sc.heights, G, 0.28, 0.12)
    z, _, zdd = vg.running_step(dt, 60, 140)
    w = row_weights(z, zdd, G, dt)
    rng = np.random.default_rng(3)
    p = rng.normal(scale=0.1, size=len(z))
    v0, v1 = 0.4, 0.7
    c = Horizon(w, dt).solve(p, v0, v1)
    assert (c[1] - c[0]) / dt == pytest.approx(v0, abs=1e-9)
    assert (c[-1] - c[-2]) / dt == pytest.approx(v1, abs=1e-9)
    acc = (c[2:] - 2 * c[1:-1] + c[:-2]) / dt**2
    stance = w[1:-1] > 0
    zi, zddi = z[1:-1][stance], zdd[1:-1][stance]
    zmp = c[1:-1][stance] - zi / (zddi + G) * acc[stance]
    np.testing.assert_allclose(zmp, p[1:-1][stance], atol=1e-8)
    # flight rows, eq. (14): zero horizontal acceleration
    assert np.max(np.abs(acc[~stance])) < 1e-8


def test_printed_eq9_denominator_is_a_typo():
    """Solve eq. (13) for a CoM, then recover the ZMP: eq. (2) with (c''^z + g) gives it back, the
    printed (c^z + g) misses it by centimetres at the stance samples."""
    dt = 0.002
    sc = gaitshift.load_scenario("paper003-variable-speed")
    z, _, zdd = stance_profiles(sc.heights, G, 0.28, 0.12).running_step(dt, 60, 140)
    w = row_weights(z, zdd, G, dt)
    p = np.full(len(z), 0.1)
    c = Horizon(w, dt).solve(p, 0.3, 0.9)
    acc = (c[2:] - 2 * c[1:-1] + c[:-2]) / dt**2
    st = w[1:-1] > 0
    zi, zddi, ci, ai = z[1:-1][st], zdd[1:-1][st], c[1:-1][st], acc[st]
    assert np.max(np.abs(ci - zi / (zddi + G) * ai - 0.1)) < 1e-8
    assert np.max(np.abs(ci - zi / (zi + G) * ai - 0.1)) > 0.01
