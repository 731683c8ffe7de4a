"""Small pieces of the whole-body QP: least-squares tasks, the cross-product matrix, rotation errors,
friction pyramids, and the QP solve with a fallback solver."""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np
import qpsolvers


def skew(v: np.ndarray) -> np.ndarray:
    """[v]x, (3, 3): skew(v) @ w = v x w."""
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def add_task(P: np.ndarray, qv: np.ndarray, A: np.ndarray, b: np.ndarray, w: float, cols: slice) -> None:
    """Add the least-squares task ``w ||A x[cols] - b||^2`` to the QP cost ``x^T P x / 2 + qv^T x``."""
    P[cols, cols] += w * A.T @ A
    qv[cols] -= w * A.T @ b


def rotation_error(R_ref: np.ndarray, R: np.ndarray) -> np.ndarray:
    """World-frame rotation vector e with exp([e]) R = R_ref, rad, (3,)."""
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, (R_ref @ R.T).ravel())
    e = np.empty(3)
    mujoco.mju_quat2Vel(e, quat, 1.0)
    return e


def friction_rows(n: int, k: int, col0: int, mu: float) -> np.ndarray:
    """Rows (4k, n) of the friction pyramids ``|f_x|, |f_y| <= mu f_z`` of k point forces stored from
    column ``col0`` as (f_x, f_y, f_z) triples: G x <= 0."""
    fr = np.zeros((4 * k, n))
    i = np.arange(k)
    c0 = col0 + 3 * i
    for r, (axis, sign) in enumerate(((0, 1.0), (0, -1.0), (1, 1.0), (1, -1.0))):
        fr[4 * i + r, c0 + axis] = sign
        fr[4 * i + r, c0 + 2] = -mu
    return fr


def solve_qp(cost: tuple[np.ndarray, np.ndarray], ineq: Any, eq: tuple[np.ndarray, np.ndarray]) -> tuple[Any, str]:
    """min x^T P x / 2 + q^T x s.t. G x <= h, lb <= x <= ub, A x = b with ``cost`` (P, q), ``ineq``
    (G, h, lb, ub), ``eq`` (A, b): daqp, then quadprog if daqp fails. Returns (x or None, solver)."""
    P, q = cost
    G, h, lb, ub = ineq
    A, b = eq
    solver = "daqp"
    for solver in ("daqp", "quadprog"):
        try:
            x = qpsolvers.solve_qp(P, q, G, h, A, b, lb=lb, ub=ub, solver=solver)
        except Exception:
            x = None
        if x is not None:
            return x, solver
    return None, solver
