"""Small pieces of the whole-body QP: the cross-product matrix, rotation errors and the QP solve (daqp
called directly, quadprog through ``qpsolvers`` as the fallback)."""

from __future__ import annotations

import math
from typing import Any

import daqp
import mujoco
import numpy as np
import qpsolvers

#: what stands for an absent bound in the daqp form (daqp's own convention)
INF = 1e30

#: daqp's exit flag for a problem with no feasible point (``DAQP_EXIT_INFEASIBLE``)
DAQP_INFEASIBLE = -1

#: (3, 9): ``v @ SKEW_BASIS`` is the row-major flattened [v]x (for v of any leading shape)
SKEW_BASIS = np.zeros((3, 9))
SKEW_BASIS[[2, 1, 2, 0, 1, 0], [1, 2, 3, 5, 6, 7]] = [-1.0, 1.0, 1.0, -1.0, -1.0, 1.0]


def skew(v: np.ndarray) -> np.ndarray:
    """[v]x of one vector (3,) or of a stack (..., 3), shape (..., 3, 3): skew(v) @ w = v x w."""
    v = np.asarray(v, float)
    return (v @ SKEW_BASIS).reshape(*v.shape[:-1], 3, 3)


def rotation_error(R_ref: np.ndarray, R: np.ndarray) -> np.ndarray:
    """World-frame rotation vector e with exp([e]) R = R_ref, rad, (3,)."""
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, (R_ref @ R.T).ravel())
    e = np.empty(3)
    mujoco.mju_quat2Vel(e, quat, 1.0)
    return e


def quat_yaw_error(yaw: float, pitch: float, w: float, x: float, y: float, z: float) -> tuple[float, float, float]:
    """The rotation vector (rad) of ``q_ref (x) q^-1``, ``q = (w, x, y, z)`` a unit quaternion and
    ``q_ref = (cos(yaw/2), 0, 0, sin(yaw/2)) (x) (cos(pitch/2), 0, -sin(pitch/2), 0)`` (the rotation
    ``rot_z(yaw) @ rot_y(-pitch)``), on Python floats: the same steps as MuJoCo's ``mju_mulQuat``
    and ``mju_quat2Vel`` (angle ``2 atan2(|v|, w)``, taken in (-pi, pi]) for a few scalars."""
    cy, sy = math.cos(0.5 * yaw), math.sin(0.5 * yaw)
    if pitch != 0.0:
        cp, sp = math.cos(0.5 * pitch), math.sin(0.5 * pitch)
        a, b, c, d = cy * cp, sy * sp, -cy * sp, sy * cp
    else:
        a, b, c, d = cy, 0.0, 0.0, sy
    # (a, b, c, d) (x) (w, -x, -y, -z)
    ew = a * w + b * x + c * y + d * z
    ex = -a * x + b * w - c * z + d * y
    ey = -a * y + b * z + c * w - d * x
    ez = -a * z - b * y + c * x + d * w
    s = math.sqrt(ex * ex + ey * ey + ez * ez)
    if s < mujoco.mjMINVAL:
        return 0.0, 0.0, 0.0
    angle = 2.0 * math.atan2(s, ew)
    if angle > math.pi:
        angle -= 2.0 * math.pi
    k = angle / s
    return ex * k, ey * k, ez * k


def yaw_error(yaw: float, quat: np.ndarray, pitch: float = 0.0) -> np.ndarray:
    """:func:`rotation_error` of the orientation of unit quaternion ``quat`` (w, x, y, z) toward
    ``rot_z(yaw) @ rot_y(-pitch)`` (a sole pitched with a ramp rising by ``pitch`` along its heading),
    computed on quaternions (:func:`quat_yaw_error`): the rotation vector of ``q_ref (x) quat^-1``,
    rad, (3,)."""
    return np.array(quat_yaw_error(yaw, pitch, *(float(v) for v in quat)))


def solve_qp(
    H: np.ndarray, f: np.ndarray, A: np.ndarray, bu: np.ndarray, bl: np.ndarray, sense: np.ndarray
) -> tuple[Any, str]:
    """min x^T H x / 2 + f^T x  s.t.  bl[:n] <= x <= bu[:n],  bl[n:] <= A x <= bu[n:]; ``sense`` (n + m,)
    int: 5 marks an equality row (bl = bu there), 0 an inequality; bounds of magnitude >= :data:`INF`
    are absent. daqp (dual active set, cold start: warm starts were measured not to help,
    docs/simulation.md "Controller tick"), then quadprog if daqp fails, except on a problem daqp proves
    infeasible (quadprog found no point on any of the 463 such QPs of the single-support bench, at
    about 0.5 ms each). Returns (x (n,) or None, solver)."""
    try:
        x, _, flag, _ = daqp.solve(H, f, A, bu, bl, sense.copy())
    except Exception:
        flag = 0  # daqp itself failed
    if flag > 0:
        return x, "daqp"
    if flag == DAQP_INFEASIBLE:
        return None, "daqp"
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
