"""Closed-form solutions of the time-varying LIPM (paper 001, eqs. (1)-(6)).

During support (DS or SS) with constant stiffness T and a ZMP moving linearly from c0 to c1 over the
phase duration tau, eq. (1)

    p''(t) = (p(t) - c(t)) / T^2 - g e_z

has the closed-form solution (eqs. (3)-(4)), with e0 = p0 - c0 - g T^2 e_z and cd = (c1 - c0)/tau:

    p(t) = c(t) + g T^2 e_z + e0 cosh(t/T) + T (v0 - cd) sinh(t/T)
    v(t) = cd + e0/T sinh(t/T) + (v0 - cd) cosh(t/T)
    a(t) = e0/T^2 cosh(t/T) + (v0 - cd)/T sinh(t/T)          (= (p - c)/T^2 - g e_z)

In flight the CoM is ballistic (eqs. (5)-(6), with the sign of gravity corrected, see
docs/equations.md): p(t) = p0 + v0 t - g t^2/2 e_z, v(t) = v0 - g t e_z.

All functions broadcast over leading axes; positions are m, velocities m/s, times s.
"""

from __future__ import annotations

import math
from typing import TypeAlias, overload

import numpy as np

from gaitshift.models.arrays import FloatArray, FloatLike


def support_state(
    p0: FloatArray, v0: FloatArray, c0: FloatArray, c1: FloatArray, T: FloatLike, tau: FloatLike, t: FloatLike, g: float
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """CoM position, velocity, acceleration at time ``t`` into a support phase (eqs. (1)-(4)).

    Args:
        p0, v0: CoM position and velocity at the phase start, shape (..., 3).
        c0, c1: ZMP at the phase start and end, shape (..., 3).
        T: stiffness, s, shape (...).
        tau: phase duration, s, shape (...).
        t: time since the phase start, s, shape (...).
        g: gravity magnitude, m/s^2.

    Returns:
        (p, v, a, c), each shape (..., 3): CoM position, velocity, acceleration and the ZMP at t.
    """
    T = np.asarray(T, float)[..., None]
    tau = np.asarray(tau, float)[..., None]
    t = np.asarray(t, float)[..., None]
    ez = np.array([0.0, 0.0, 1.0])
    cd = (c1 - c0) / tau
    e0 = p0 - c0 - g * T**2 * ez
    ed = v0 - cd
    ch, sh = np.cosh(t / T), np.sinh(t / T)
    c = c0 + cd * t
    p = c + g * T**2 * ez + e0 * ch + T * ed * sh
    v = cd + e0 / T * sh + ed * ch
    a = e0 / T**2 * ch + ed / T * sh
    return p, v, a, c


def flight_state(p0: FloatArray, v0: FloatArray, t: FloatLike, g: float) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Ballistic CoM position, velocity and acceleration ``t`` s after take-off (eqs. (5)-(6)).

    Shapes: p0, v0 (..., 3); t (...). Returns (p, v, a), each (..., 3).
    """
    t = np.asarray(t, float)[..., None]
    ez = np.array([0.0, 0.0, 1.0])
    p = p0 + v0 * t - 0.5 * g * t**2 * ez
    v = v0 - g * t * ez
    a = np.broadcast_to(-g * ez, p.shape).copy()
    return p, v, a


#: (z1, v1, (dz1/dz, dz1/dv, dz1/dT), (dv1/dz, dv1/dv, dv1/dT)) of :func:`support_map_1d`
SupportMap: TypeAlias = tuple[float, float, tuple[float, float, float], tuple[float, float, float]]
SupportMapArrays: TypeAlias = tuple[
    FloatLike, FloatLike, tuple[FloatLike, FloatLike, FloatLike], tuple[FloatLike, FloatLike, FloatLike]
]


@overload
def support_map_1d(z: float, v: float, T: float, tau: float, g: float, c: float = 0.0) -> SupportMap: ...
@overload
def support_map_1d(
    z: FloatLike, v: FloatLike, T: FloatLike, tau: FloatLike, g: float, c: FloatLike = 0.0
) -> SupportMapArrays: ...
def support_map_1d(
    z: FloatLike, v: FloatLike, T: FloatLike, tau: FloatLike, g: float, c: FloatLike = 0.0
) -> SupportMapArrays:
    """Vertical support map with constant ZMP height ``c`` and its partial derivatives.

    Returns ``(z1, v1, dz1, dv1)`` where dz1 and dv1 are tuples of partials with respect to
    (z, v, T). Broadcasts over all inputs. Used by the stiffness root finding (eqs. (9)-(14)).
    """
    a = tau / T
    ch: FloatLike
    sh: FloatLike
    if isinstance(a, float):  # scalar fast path: math is ~20x faster than numpy on 0-d values
        ch, sh = math.cosh(a), math.sinh(a)
    else:
        ch, sh = np.cosh(a), np.sinh(a)
    e = z - c - g * T**2
    z1 = c + g * T**2 + e * ch + T * v * sh
    v1 = e * sh / T + v * ch
    dz1_dT = 2 * g * T * (1 - ch) - e * sh * a / T + v * sh - v * ch * a
    dv1_dT = -2 * g * sh - e * (a * ch + sh) / T**2 - v * sh * a / T
    return z1, v1, (ch, T * sh, dz1_dT), (sh / T, ch, dv1_dT)
