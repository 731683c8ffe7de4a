"""The QP pieces of the whole-body controller against independent code.

Oracles: ``yaw_error`` (quaternions) against ``rotation_error`` (matrices, itself checked against
SciPy in test_wbc); ``solve_qp`` in daqp's two-sided form against quadprog given the one-sided form
written out here, and its quadprog fallback (daqp made to fail) against daqp's own answer; both
answers must satisfy the bounds, the two-sided rows and the equalities; a problem daqp proves
infeasible is one quadprog finds infeasible too, and it is not handed to quadprog.
"""

from __future__ import annotations

import daqp
import numpy as np
import pytest
import qpsolvers
from scipy.spatial.transform import Rotation

from gaitshift.common.rotations import rot_z
from gaitshift.control.qp_terms import INF, rotation_error, solve_qp, yaw_error


def test_yaw_error_on_quaternions_equals_the_rotation_vector_of_the_matrices():
    rng = np.random.default_rng(3)
    for _ in range(50):
        R = Rotation.random(random_state=rng)
        yaw = rng.uniform(-7.0, 7.0)
        quat = R.as_quat(scalar_first=True) * rng.choice([-1.0, 1.0])  # q and -q: the same rotation
        np.testing.assert_allclose(yaw_error(yaw, quat), rotation_error(rot_z(yaw), R.as_matrix()), atol=1e-12)
        pitch = rng.uniform(-0.5, 0.5)  # a sole on a ramp: rot_z(yaw) rot_y(-pitch)
        R_ref = rot_z(yaw) @ Rotation.from_rotvec([0.0, -pitch, 0.0]).as_matrix()
        np.testing.assert_allclose(yaw_error(yaw, quat, pitch), rotation_error(R_ref, R.as_matrix()), atol=1e-12)


def _problem(seed: int = 0):
    """A random strictly convex QP with box bounds on some unknowns, two-sided and one-sided rows and
    two equalities, feasible at x = 0 shifted by a known point."""
    rng = np.random.default_rng(seed)
    n, m = 12, 10
    L = rng.normal(size=(n, n))
    H = L @ L.T + 0.1 * np.eye(n)
    f = rng.normal(size=n) * 5.0
    A = rng.normal(size=(m, n))
    x0 = rng.normal(size=n) * 0.1
    r = A @ x0
    bu = np.concatenate([np.full(n, INF), r + 0.2])
    bl = np.concatenate([np.full(n, -INF), r - 0.3])
    bu[:3], bl[:3] = x0[:3] + 0.05, x0[:3] - 0.05  # boxes on three unknowns
    bl[n + 4 : n + 6] = -INF  # one-sided rows
    bu[n + 8 :] = bl[n + 8 :] = r[8:]  # two equalities
    sense = np.zeros(n + m, dtype=np.intc)
    sense[n + 8 :] = 5
    return H, f, A, bu, bl, sense


def _check_feasible(x, A, bu, bl):
    n = len(x)
    assert np.all(x <= bu[:n] + 1e-7) and np.all(x >= bl[:n] - 1e-7)
    Ax = A @ x
    assert np.all(Ax <= bu[n:] + 1e-7) and np.all(Ax >= bl[n:] - 1e-7)


def test_daqp_two_sided_form_matches_quadprog_on_the_one_sided_form():
    H, f, A, bu, bl, sense = _problem()
    x, solver = solve_qp(H, f, A, bu, bl, sense)
    assert solver == "daqp"
    n = len(f)
    eq = sense[n:] == 5
    up, lo = ~eq & (bu[n:] < INF), ~eq & (bl[n:] > -INF)
    G = np.vstack([A[up], -A[lo]])
    h = np.concatenate([bu[n:][up], -bl[n:][lo]])
    lb, ub = np.where(bl[:n] > -INF, bl[:n], -np.inf), np.where(bu[:n] < INF, bu[:n], np.inf)
    ref = qpsolvers.solve_qp(H, f, G, h, A[eq], bu[n:][eq], lb=lb, ub=ub, solver="quadprog")
    np.testing.assert_allclose(x, ref, atol=1e-6)
    _check_feasible(x, A, bu, bl)


def test_quadprog_fallback_gives_daqps_answer(monkeypatch: pytest.MonkeyPatch):
    H, f, A, bu, bl, sense = _problem(1)
    x_daqp, _ = solve_qp(H, f, A, bu, bl, sense)

    def broken(*args, **kwargs):
        raise RuntimeError("daqp made to fail")

    monkeypatch.setattr(daqp, "solve", broken)
    x, solver = solve_qp(H, f, A, bu, bl, sense)
    assert solver == "quadprog"
    np.testing.assert_allclose(x, x_daqp, atol=1e-6)
    _check_feasible(x, A, bu, bl)


def test_a_problem_daqp_proves_infeasible_is_not_handed_to_quadprog(monkeypatch: pytest.MonkeyPatch):
    H, f, A, bu, bl, sense = _problem(2)
    n = len(f)
    A[1] = A[0]  # rows 0 and 1 alike: a x <= u and a x >= u + 1
    bl[n], bl[n + 1], bu[n + 1] = -INF, bu[n] + 1.0, INF
    one_sided = qpsolvers.solve_qp(H, f, np.vstack([A[:1], -A[1:2]]), np.array([bu[n], -bl[n + 1]]), solver="quadprog")
    assert one_sided is None  # quadprog finds no point either
    calls = []
    monkeypatch.setattr(qpsolvers, "solve_qp", lambda *a, **k: calls.append(1))
    x, solver = solve_qp(H, f, A, bu, bl, sense)
    assert x is None and solver == "daqp" and not calls
