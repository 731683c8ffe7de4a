"""Small pieces of the whole-body QP: the cross-product matrix, rotation errors, friction pyramids,
and the QP solve (daqp called directly, quadprog through ``qpsolvers`` as the fallback)."""

from __future__ import annotations

import math
from typing import Any

import daqp
import mujoco
import numpy as np
import qpsolvers

#: what stands for an absent bound in the daqp form (daqp's own convention)
INF = 1e30

#: (3, 9): ``v @ _SKEW`` is the row-major flattened [v]x
_SKEW = np.zeros((3, 9))
_SKEW[[2, 1, 2, 0, 1, 0], [1, 2, 3, 5, 6, 7]] = [-1.0, 1.0, 1.0, -1.0, -1.0, 1.0]


def skew(v: np.ndarray) -> np.ndarray:
    """[v]x of one vector (3,) or of a stack (..., 3), shape (..., 3, 3): skew(v) @ w = v x w."""
    v = np.asarray(v, float)
    return (v @ _SKEW).reshape(*v.shape[:-1], 3, 3)


def rotation_error(R_ref: np.ndarray, R: np.ndarray) -> np.ndarray:
    """World-frame rotation vector e with exp([e]) R = R_ref, rad, (3,)."""
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, (R_ref @ R.T).ravel())
    e = np.empty(3)
    mujoco.mju_quat2Vel(e, quat, 1.0)
    return e


def yaw_error(yaw: float, quat: np.ndarray, pitch: float = 0.0) -> np.ndarray:
    """:func:`rotation_error` of the orientation of unit quaternion ``quat`` (w, x, y, z) toward
    ``rot_z(yaw) @ rot_y(-pitch)`` (a sole pitched with a ramp rising by ``pitch`` along its heading),
    computed on quaternions: the rotation vector of ``q_ref (x) quat^-1``, rad, (3,)."""
    q_ref = np.array([math.cos(0.5 * yaw), 0.0, 0.0, math.sin(0.5 * yaw)])
    if pitch != 0.0:
        mujoco.mju_mulQuat(q_ref, q_ref, np.array([math.cos(0.5 * pitch), 0.0, -math.sin(0.5 * pitch), 0.0]))
    q_inv = np.empty(4)
    mujoco.mju_negQuat(q_inv, quat)
    mujoco.mju_mulQuat(q_ref, q_ref, q_inv)
    e = np.empty(3)
    mujoco.mju_quat2Vel(e, q_ref, 1.0)
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


def solve_qp(
    H: np.ndarray, f: np.ndarray, A: np.ndarray, bu: np.ndarray, bl: np.ndarray, sense: np.ndarray
) -> tuple[Any, str]:
    """min x^T H x / 2 + f^T x  s.t.  bl[:n] <= x <= bu[:n],  bl[n:] <= A x <= bu[n:]; ``sense`` (n + m,)
    int: 5 marks an equality row (bl = bu there), 0 an inequality; bounds of magnitude >= :data:`INF`
    are absent. daqp (dual active set, cold start: warm starts were measured not to help,
    docs/simulation.md "Controller tick"), then quadprog if daqp fails. Returns (x (n,) or None, solver)."""
    try:
        x, _, flag, _ = daqp.solve(H, f, A, bu, bl, sense.copy())
    except Exception:
        flag = -1
    if flag > 0:
        return x, "daqp"
    return _quadprog(H, f, A, bu, bl, sense), "quadprog"


def _quadprog(H: np.ndarray, f: np.ndarray, A: np.ndarray, bu: np.ndarray, bl: np.ndarray, sense: np.ndarray) -> Any:
    """The same QP in the one-sided ``qpsolvers`` form, solved by quadprog; None when that fails too."""
    n = len(f)
    eq = sense[n:] == 5
    upper, lower = ~eq & (bu[n:] < INF), ~eq & (bl[n:] > -INF)
    G = np.vstack([A[upper], -A[lower]])
    h = np.concatenate([bu[n:][upper], -bl[n:][lower]])
    lb = np.where(bl[:n] > -INF, bl[:n], -np.inf)
    ub = np.where(bu[:n] < INF, bu[:n], np.inf)
    Aeq, beq = (A[eq], bu[n:][eq]) if eq.any() else (None, None)
    try:
        return qpsolvers.solve_qp(H, f, G, h, Aeq, beq, lb=lb, ub=ub, solver="quadprog")
    except Exception:
        return None
