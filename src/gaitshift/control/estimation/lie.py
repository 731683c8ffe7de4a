"""SO(3) and SE_K(3) helpers of the estimators, on the hot path (one call per 2 ms tick).

Group operations off the hot path come from mink's :mod:`mink.lie` (``SO3.exp``, ``log``, ``from_matrix``).
On the per-tick path the filters call the C routines mink itself wraps (``mju_quatIntegrate``,
``mju_mulQuat``, ``mju_quat2Mat``) on preallocated arrays, with the SE_K(3) blocks from
:func:`exp_blocks`: :func:`gaitshift.bench.estimation.lie_costs` measures mink's
object API, a closed-form Rodrigues formula in ``math`` (:func:`rodrigues`) and the in-place calls, and
``docs/estimation.md`` reports the numbers that chose the in-place route.

Formulas (Barfoot, *State Estimation for Robotics*, 2017, eqs. 7.14 and 7.86)::

    Exp(phi)  = I + sin(t)/t [phi]x + (1 - cos t)/t^2 [phi]x^2,                  t = |phi|
    J_l(phi)  = I + (1 - cos t)/t^2 [phi]x + (t - sin t)/t^3 [phi]x^2             (left Jacobian)
    Exp_SE_K(3)(xi) = [[Exp(phi), J_l(phi) rho_1, ..., J_l(phi) rho_K], [0, I]]  (Hartley 2018, eq. 13)
"""

from __future__ import annotations

import math

import numpy as np
from mink.lie import SO3

#: (3, 9) map from a vector to its flattened skew matrix: ``skew(w).ravel() == w @ SKEW``.
SKEW = np.zeros((3, 9))
for _row, _col, _axis, _sign in (
    (0, 1, 2, -1.0),
    (0, 2, 1, 1.0),
    (1, 0, 2, 1.0),
    (1, 2, 0, -1.0),
    (2, 0, 1, -1.0),
    (2, 1, 0, 1.0),
):
    SKEW[_axis, 3 * _row + _col] = _sign


def skew(w: np.ndarray) -> np.ndarray:
    """Skew matrices ``[w]x`` with ``[w]x v = w x v``: (3,) -> (3, 3), or (n, 3) -> (n, 3, 3)."""
    w = np.asarray(w, dtype=float)
    return (w @ SKEW).reshape(*w.shape[:-1], 3, 3)


def exp_so3(phi: np.ndarray) -> np.ndarray:
    """Rotation matrix ``Exp(phi)`` (3, 3) of a rotation vector (3,), rad (mink ``SO3.exp``)."""
    return SO3.exp(np.asarray(phi, dtype=float)).as_matrix()


def log_so3(rot: np.ndarray) -> np.ndarray:
    """Rotation vector (3,) of a rotation matrix (3, 3), rad, angle in [0, pi] (mink ``SO3.log``)."""
    return SO3.from_matrix(np.asarray(rot, dtype=float)).log()


def rodrigues(phi: np.ndarray) -> np.ndarray:
    """``Exp(phi)`` (3, 3) by the closed-form Rodrigues formula in ``math`` (the benchmark's candidate)."""
    x, y, z = (float(c) for c in phi)
    t2 = x * x + y * y + z * z
    t = math.sqrt(t2)
    if t < 1e-8:
        a, b = 1.0 - t2 / 6.0, 0.5 - t2 / 24.0
    else:
        a, b = math.sin(t) / t, (1.0 - math.cos(t)) / t2
    return np.array(
        [
            [1.0 - b * (y * y + z * z), b * x * y - a * z, b * x * z + a * y],
            [b * x * y + a * z, 1.0 - b * (x * x + z * z), b * y * z - a * x],
            [b * x * z - a * y, b * y * z + a * x, 1.0 - b * (x * x + y * y)],
        ]
    )


def exp_blocks(x: float, y: float, z: float) -> tuple[tuple[float, ...], tuple[float, float, float, float]]:
    """Blocks of ``Exp`` on SE_K(3) for ``phi = (x, y, z)``, from one sin/cos evaluation.

    Returns ``([Exp(phi)^T ; J_l(phi)^T]`` row-major (18 floats), the quaternion (w, x, y, z) of
    ``Exp(phi)``), with ``[phi]x^2 = phi phi^T - t^2 I`` (Barfoot 2017, eqs. 7.14 and 7.86)::

        Exp^T = (1 - b_e t^2) I - a_e [phi]x + b_e phi phi^T,  a_e = sin t / t,  b_e = (1 - cos t)/t^2
        J_l^T = (1 - b_j t^2) I - a_j [phi]x + b_j phi phi^T,  a_j = b_e,  b_j = (t - sin t)/t^3

    (Taylor series below t = 1e-4 rad)."""
    t2 = x * x + y * y + z * z
    if t2 < 1e-8:
        ae, be, bj = 1.0 - t2 / 6.0, 0.5 - t2 / 24.0, 1.0 / 6.0 - t2 / 120.0
        half_sin, half_cos = 0.5 - t2 / 48.0, 1.0 - t2 / 8.0
    else:
        t = math.sqrt(t2)
        sin_t, cos_t = math.sin(t), math.cos(t)
        ae, be, bj = sin_t / t, (1.0 - cos_t) / t2, (t - sin_t) / (t2 * t)
        half_sin, half_cos = math.sin(0.5 * t) / t, math.cos(0.5 * t)
    xx, yy, zz, xy, xz, yz = x * x, y * y, z * z, x * y, x * z, y * z
    blocks = []
    for a, b in ((ae, be), (be, bj)):
        c = 1.0 - b * t2
        blocks += [c + b * xx, b * xy + a * z, b * xz - a * y]
        blocks += [b * xy - a * z, c + b * yy, b * yz + a * x]
        blocks += [b * xz + a * y, b * yz - a * x, c + b * zz]
    return tuple(blocks), (half_cos, half_sin * x, half_sin * y, half_sin * z)


def quat_exp(x: float, y: float, z: float) -> tuple[float, float, float, float]:
    """Unit quaternion (w, x, y, z) of ``Exp((x, y, z))`` (series below 1e-6 rad)."""
    t2 = x * x + y * y + z * z
    if t2 < 1e-12:
        s, c = 0.5 - t2 / 48.0, 1.0 - t2 / 8.0
    else:
        t = math.sqrt(t2)
        s, c = math.sin(0.5 * t) / t, math.cos(0.5 * t)
    return (c, s * x, s * y, s * z)


def log_rot(m: list[float]) -> tuple[float, float, float]:
    """Rotation vector of a rotation matrix given row-major as 9 floats, rad (angle < pi)::

    Log(M) = t / (2 sin t) (m21 - m12, m02 - m20, m10 - m01),   cos t = (tr M - 1) / 2."""
    vx, vy, vz = 0.5 * (m[7] - m[5]), 0.5 * (m[2] - m[6]), 0.5 * (m[3] - m[1])
    s = math.sqrt(vx * vx + vy * vy + vz * vz)
    c = 0.5 * (m[0] + m[4] + m[8] - 1.0)
    f = 1.0 + s * s / 6.0 if s < 1e-6 else math.atan2(s, c) / s
    return (f * vx, f * vy, f * vz)


def quat_of_mat(rot: np.ndarray) -> np.ndarray:
    """Unit quaternion (4,) (w, x, y, z) of a rotation matrix (3, 3), w >= 0 (mink ``SO3.from_matrix``)."""
    quat = SO3.from_matrix(np.asarray(rot, dtype=float)).wxyz.copy()
    return quat if quat[0] >= 0.0 else -quat


def mat_of_quat(quat: np.ndarray) -> np.ndarray:
    """Rotation matrix (3, 3) of a unit quaternion (4,) (w, x, y, z) (mink ``SO3.as_matrix``)."""
    return SO3(wxyz=np.asarray(quat, dtype=float)).as_matrix()
