"""Algorithm 1 of paper 003: the speed-guided foothold iteration (tol 1e-6, <= 10 iterations).

Oracle: an independent dense solve of eq. (13) with the returned foothold must start at the given CoM
with the given velocities.
"""

from __future__ import annotations

import numpy as np
import pytest

import gaitshift
from gaitshift.models.tridiagonal import Horizon, tridiagonal_system
from gaitshift.models.vhip import row_weights, stance_profiles
from gaitshift.planners.vhip.foothold import target_foothold

G, DT = 9.81, 0.004


@pytest.fixture(scope="module")
def horizon():
    sc = gaitshift.load_scenario("paper003-variable-speed")
    z, _, zdd = stance_profiles(sc.heights, G, 0.28, 0.12).running_step(DT, 30, 70)
    return Horizon(row_weights(z, zdd, G, DT), DT)


def _dense(h, p, v0, v1):
    lo, di, up = tridiagonal_system(h.w)
    A = np.diag(di) + np.diag(up, 1) + np.diag(lo, -1)
    rhs = h.w[:, None] * np.asarray(p)[None, :]
    rhs[0], rhs[-1] = np.asarray(v0) * DT, np.asarray(v1) * DT
    return np.linalg.solve(A, rhs)


def test_foothold_iteration_converges_within_ten_iterations(horizon):
    rng = np.random.default_rng(4)
    for _ in range(50):
        c_prev = rng.normal(scale=2.0, size=2)
        v_prev, v_cmd = rng.uniform(-1.5, 1.5, 2), rng.uniform(-1.5, 1.5, 2)
        p_nom = c_prev + rng.normal(scale=0.3, size=2)
        res = target_foothold(horizon, c_prev, v_prev, v_cmd, p_nom)
        assert np.all(res.iterations <= 10)
        assert np.all(res.residual <= 1e-6)
        # the returned CoM satisfies every row of eq. (13) with the returned foothold (residuals,
        # no solve), and starts at the previous CoM
        c, w = res.com, horizon.w[1:-1, None]
        rows = -c[:-2] + (2 + w) * c[1:-1] - c[2:] - w * res.foothold
        assert np.max(np.abs(rows)) < 1e-12
        np.testing.assert_allclose(c[0], c_prev, atol=1e-6)
        np.testing.assert_allclose((c[1] - c[0]) / DT, v_prev, atol=1e-8)
        np.testing.assert_allclose((c[-1] - c[-2]) / DT, v_cmd, atol=1e-8)


def test_one_iteration_suffices_because_a_zmp_shift_shifts_the_com(horizon):
    """Translation invariance of eq. (13): the update p <- p - dc is exact after one step."""
    v0, v1 = np.array([0.3, -0.2]), np.array([0.6, 0.2])
    c_a = _dense(horizon, np.array([0.0, 0.0]), v0, v1)
    c_b = _dense(horizon, np.array([0.37, -0.11]), v0, v1)
    np.testing.assert_allclose(c_b - c_a, np.broadcast_to([0.37, -0.11], c_a.shape), atol=1e-10)
    res = target_foothold(horizon, np.array([1.0, 0.2]), v0, v1, np.array([1.5, -0.4]))
    assert res.iterations.tolist() == [1, 1]


def test_exact_nominal_needs_no_iteration(horizon):
    v0, v1 = np.array([0.5, 0.1]), np.array([0.5, -0.1])
    first = target_foothold(horizon, np.zeros(2), v0, v1, np.zeros(2))
    again = target_foothold(horizon, np.zeros(2), v0, v1, first.foothold)
    assert again.iterations.tolist() == [0, 0]
    np.testing.assert_allclose(again.foothold, first.foothold, atol=1e-12)
