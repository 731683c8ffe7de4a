"""The sextic of paper 003 eqs. (5)-(6) meets its seven boundary conditions, and the one 4x4 system
serves both the stance CoM height and the swing-foot height.

Oracle: the monomials and their first two derivatives evaluated by hand (no gaitshift code).
"""

from __future__ import annotations

import numpy as np

from gaitshift.gait.swing import sextic_height_coefficients
from gaitshift.models.sextic import SEXTIC_INVERSE, SEXTIC_MATRIX, sextic_coefficients


def _value_rate_acc(coef: np.ndarray, t: float) -> tuple[float, float, float]:
    """z(t), z'(t), z''(t) of the polynomial sum_k coef_k t^k, from the monomials directly."""
    k = np.arange(7)
    return (
        float(np.sum(coef * t**k)),
        float(np.sum(coef[1:] * k[1:] * t ** (k[1:] - 1))),
        float(np.sum(coef[2:] * k[2:] * (k[2:] - 1) * t ** (k[2:] - 2))),
    )


def test_sextic_meets_its_seven_boundary_conditions():
    rng = np.random.default_rng(1)
    for _ in range(5):
        T = rng.uniform(0.15, 0.5)
        z0, z1, zl = rng.uniform(0.7, 0.9, 3)
        v0, v1, a0, a1 = rng.normal(size=4)
        coef = sextic_coefficients(T, z0, v0, a0, zl, z1, v1, a1)
        start, mid, end = (_value_rate_acc(coef, t) for t in (0.0, T / 2, T))
        np.testing.assert_allclose([*start, mid[0], *end], [z0, v0, a0, zl, z1, v1, a1], atol=1e-9)


def test_swing_height_sextic_meets_its_seven_conditions_through_the_same_matrix():
    """Apex at u = 1/2, z0 and z1 at the ends, zero velocity and acceleration at both ends."""
    np.testing.assert_allclose(SEXTIC_MATRIX @ SEXTIC_INVERSE, np.eye(4), atol=1e-12)
    rng = np.random.default_rng(2)
    z0, z1 = rng.uniform(-0.1, 0.2, 2)
    apex = max(z0, z1) + 0.08
    coef = sextic_height_coefficients(z0, z1, apex)
    start, mid, end = (_value_rate_acc(coef, u) for u in (0.0, 0.5, 1.0))
    np.testing.assert_allclose([*start, mid[0], *end], [z0, 0.0, 0.0, apex, z1, 0.0, 0.0], atol=1e-12)
