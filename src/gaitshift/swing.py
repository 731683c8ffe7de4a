"""Swing-foot trajectories: smooth polynomials from lift-off to touchdown.

Horizontal position and yaw follow a quintic ("minimum-jerk") blend ``s(u) = 10u^3 - 15u^4 + 6u^5``,
u = (t - t0)/(t1 - t0) in [0, 1], with zero velocity and acceleration at both ends. Height follows the
sextic polynomial of paper 003 (§3.3) with seven conditions: z(0) = z0, z(1) = z1, zero velocity and
acceleration at both ends, and z(1/2) = max(z0, z1) + clearance (the apex).
"""

from __future__ import annotations

import numpy as np

# rows: z(1) - z0, z'(1), z''(1), z(1/2) - z0 as linear functions of a3..a6 (with a0=z0, a1=a2=0)
_SEXTIC_INV = np.linalg.inv(np.array([[1.0, 1.0, 1.0, 1.0],
                                      [3.0, 4.0, 5.0, 6.0],
                                      [6.0, 12.0, 20.0, 30.0],
                                      [0.5**3, 0.5**4, 0.5**5, 0.5**6]]))


def min_jerk(u: np.ndarray) -> np.ndarray:
    """Blend s(u) = 10u^3 - 15u^4 + 6u^5, shape of ``u``; s(0)=0, s(1)=1, s', s'' zero at both ends."""
    u = np.clip(u, 0.0, 1.0)
    return u**3 * (10.0 + u * (-15.0 + 6.0 * u))


def sextic_height_coefficients(z0: np.ndarray, z1: np.ndarray, apex: np.ndarray) -> np.ndarray:
    """Coefficients a_0..a_6 (in u) of the sextic with z(0)=z0, z(1)=z1, z(1/2)=apex and zero
    velocity and acceleration at u=0 and u=1. Inputs broadcast; output shape (..., 7).

    With a_0 = z0 and a_1 = a_2 = 0, the remaining four coefficients solve a fixed 4x4 system.
    """
    z0, z1, apex = np.broadcast_arrays(np.asarray(z0, float), np.asarray(z1, float), np.asarray(apex, float))
    # a3..a6 = M^-1 [z1 - z0, 0, 0, apex - z0]: only columns 0 and 3 of M^-1 matter
    a36 = (z1 - z0)[..., None] * _SEXTIC_INV[:, 0] + (apex - z0)[..., None] * _SEXTIC_INV[:, 3]
    zeros = np.zeros_like(z0)[..., None]
    return np.concatenate([z0[..., None], zeros, zeros, a36], axis=-1)


def swing_path(start: np.ndarray, end: np.ndarray, clearance: float, u: np.ndarray) -> np.ndarray:
    """Foot position along a swing from ``start`` to ``end`` (each (3,) or (K, 3)) at phases ``u``.

    Args:
        start: lift-off sole position, m, shape (3,) or broadcastable to (len(u), 3).
        end: touchdown sole position, m, same shape rules.
        clearance: apex height above the higher of the two soles, m.
        u: normalised time in [0, 1], shape (K,).

    Returns:
        Positions, shape (K, 3).
    """
    u = np.clip(np.asarray(u, float), 0.0, 1.0)
    start = np.broadcast_to(np.asarray(start, float), (len(u), 3))
    end = np.broadcast_to(np.asarray(end, float), (len(u), 3))
    s = min_jerk(u)[:, None]
    out = start + (end - start) * s
    apex = np.maximum(start[:, 2], end[:, 2]) + clearance
    coef = sextic_height_coefficients(start[:, 2], end[:, 2], apex)
    powers = u[:, None] ** np.arange(7)
    out[:, 2] = np.sum(coef * powers, axis=1)
    return out
