"""Sextic polynomials with seven boundary conditions (paper 003, eqs. (5)-(6)): the one 4x4 system.

A sextic ``z(u) = a_0 + a_1 u + ... + a_6 u^6`` on the normalised time ``u in [0, 1]`` is fixed by
its value, velocity and acceleration at ``u = 0`` and ``u = 1`` and its value at ``u = 1/2``. The
``u = 0`` conditions give ``a_0, a_1, a_2`` directly; the other four conditions are the linear system
``M (a_3, a_4, a_5, a_6) = rhs`` with the fixed matrix :data:`SEXTIC_MATRIX` (rows: ``z(1)``, ``z'(1)``,
``z''(1)``, ``z(1/2)``). The stance CoM height of paper 003 (:func:`sextic_coefficients`, solved with
``M``) and the swing-foot height (:func:`gaitshift.gait.swing.sextic_height_coefficients`, through
:data:`SEXTIC_INVERSE`) both use this one matrix.
"""

from __future__ import annotations

import numpy as np

from gaitshift.models.arrays import FloatArray

__all__ = ["SEXTIC_INVERSE", "SEXTIC_MATRIX", "sextic_coefficients", "sextic_eval"]

#: rows: z(1), z'(1), z''(1), z(1/2) as linear functions of a_3..a_6 (u = t / T)
SEXTIC_MATRIX: FloatArray = np.array(
    [[1.0, 1.0, 1.0, 1.0], [3.0, 4.0, 5.0, 6.0], [6.0, 12.0, 20.0, 30.0], [0.5**3, 0.5**4, 0.5**5, 0.5**6]]
)
#: its inverse: a_3..a_6 = SEXTIC_INVERSE @ rhs
SEXTIC_INVERSE: FloatArray = np.asarray(np.linalg.inv(SEXTIC_MATRIX), dtype=np.float64)


def sextic_coefficients(
    T: float, z0: float, v0: float, a0: float, z_mid: float, z1: float, v1: float, a1: float
) -> FloatArray:
    """Coefficients a_0..a_6 (in t, seconds) of the stance sextic, eqs. (5)-(6).

    Conditions: z(0)=z0, z'(0)=v0, z''(0)=a0, z(T/2)=z_mid, z(T)=z1, z'(T)=v1, z''(T)=a1 (m, m/s,
    m/s^2). Solved in normalised time u = t/T: the first three coefficients follow from the t=0
    conditions, the last four from :data:`SEXTIC_MATRIX`. Returns shape (7,).
    """
    b = np.empty(7)
    b[0], b[1], b[2] = z0, v0 * T, 0.5 * a0 * T * T
    rhs = np.array(
        [
            z1 - b[0] - b[1] - b[2],
            v1 * T - b[1] - 2.0 * b[2],
            a1 * T * T - 2.0 * b[2],
            z_mid - b[0] - 0.5 * b[1] - 0.25 * b[2],
        ]
    )
    b[3:] = np.linalg.solve(SEXTIC_MATRIX, rhs)
    return np.asarray(b / T ** np.arange(7), dtype=np.float64)


def sextic_eval(coef: FloatArray, t: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Height (m), velocity (m/s) and acceleration (m/s^2) of the sextic ``coef`` (7,) (from
    :func:`sextic_coefficients`) at times ``t`` (s), each shaped like ``t``."""
    t = np.asarray(t, float)
    c = np.asarray(coef, float)
    z: FloatArray = np.polynomial.polynomial.polyval(t, c)
    zd: FloatArray = np.polynomial.polynomial.polyval(t, c[1:] * np.arange(1.0, 7.0))
    zdd: FloatArray = np.polynomial.polynomial.polyval(t, c[2:] * np.arange(2.0, 7.0) * np.arange(1.0, 6.0))
    return z, zd, zdd
