"""A known flat floor: the height of a flat stance sole is a measurement of the invariant EKF.

Leg odometry and the IMU leave the base's height unobservable: each touch-down puts the new contact
point where the estimate puts it, and what the estimate got wrong in the step before stays. The error
is not a zero-mean walk: a stance sole that rolls onto its toe lifts its centre, the contact point the
filter holds still, so the filter moves the base down by the rise (docs/estimation.md, "A known
floor": the G1's estimated base height went 22 cm below the truth in 110 s of the soak). On a floor of
known height ``z_f`` (flat ground the controller is told of) a stance sole lying flat has its centre at
that height,

.. math::

    z_f = o_z + e_z^T d_i + n, \\qquad n \\sim N(0, \\sigma_f^2),                                   (1)

``d_i`` the contact point relative to the filter's local origin ``o`` (:mod:`~gaitshift.control.estimation.inekf`).
With the right-invariant error ``X = Exp(xi) X_hat``, ``d_i = Exp(xi_R) d_hat_i + J_l(xi_R) xi_di``,
so to first order

.. math::

    z_f - o_z - e_z^T \\hat d_i = H \\xi + n, \\qquad
    H = [\\hat d_{i,y}, -\\hat d_{i,x}, 0 \\mid 0 \\mid 0 \\mid e_z^T \\text{ at } \\xi_{d_i}],        (2)

the rotation columns being ``e_z^T (xi_R x d_hat_i)``. A sole whose plane is tilted from the floor's
by more than ``tilt`` (it rolls on an edge, its centre above the floor) gives no measurement, and
neither does one whose innovation is improbable (the innovation gate):

.. math::

    y_i^2 > \\gamma^2 S_{ii}, \\qquad S = H P H^T + \\sigma_f^2 I,                                 (3)

``gamma`` = :data:`GATE` standard deviations. The drift the floor corrects grows by millimetres per step
and stays inside the gate; a sole the contact detector holds in stance while it is in the air (a late
lift-off, an early touch-down) is centimetres off the floor, and pinning it there would move the base by
that much (the test: a sole held in stance 5 cm up).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["FLOOR_TILT", "GATE", "floor_correction", "floor_rows"]

#: the largest tilt, rad, of a stance sole from the floor for which its centre is taken at the floor's
#: height: a G1 sole (0.18 m long) rolled this much about an edge lifts its centre by 1.8 mm
FLOOR_TILT = 0.02
_COS_TILT = math.cos(FLOOR_TILT)
#: the innovation gate of eq. (3), in standard deviations of the innovation
GATE = 3.0


def floor_rows(
    d_hat: np.ndarray, origin_z: float, floor: float, feet: list[int], nx: int
) -> tuple[np.ndarray, np.ndarray]:
    """Eq. (2) for the soles ``feet``: the rows ``H`` (len(feet), nx) and the innovations ``y`` (len(feet),) m
    (``d_hat`` (2, 3): the contact points relative to the origin, ``origin_z`` its height, ``floor`` z_f)."""
    h = np.zeros((len(feet), nx))
    y = np.empty(len(feet))
    for r, i in enumerate(feet):
        h[r, 0], h[r, 1] = d_hat[i, 1], -d_hat[i, 0]
        h[r, 9 + 3 * i + 2] = 1.0
        y[r] = floor - origin_z - d_hat[i, 2]
    return h, y


def floor_correction(
    cov: np.ndarray,
    d_hat: np.ndarray,
    origin_z: float,
    floor: float,
    var: float,
    normal_z: np.ndarray,
    measured: tuple[bool, bool],
) -> np.ndarray | None:
    """Eq. (2)'s Kalman update for the measured stance soles lying flat: ``cov`` (nx, nx) updated in
    place, the correction ``K y`` (nx,) returned (None: no sole flat, or a singular innovation).

    Args:
        cov: the filter's covariance (local origin). d_hat: (2, 3) contact points relative to ``o``, m.
        origin_z: ``o_z``, m. floor: ``z_f``, m. var: ``sigma_f^2``, m^2.
        normal_z: (2,) the z component of each sole's normal in the world (the cosine of its tilt).
        measured: the soles in stance in the filter's state.
    """
    feet = [i for i in (0, 1) if measured[i] and normal_z[i] > _COS_TILT]
    if not feet:
        return None
    h, y = floor_rows(d_hat, origin_z, floor, feet, cov.shape[0])
    pht = cov @ h.T
    s = h @ pht + var * np.eye(len(feet))
    keep = y * y <= GATE**2 * np.diag(s)  # eq. (3): a sole off the floor is no measurement of it
    if not keep.all():
        if not keep.any():
            return None
        h, y, pht = h[keep], y[keep], pht[:, keep]
        s = s[np.ix_(keep, keep)]
    try:
        kt = np.linalg.solve(s, pht.T)  # K^T
    except np.linalg.LinAlgError:
        return None
    cov -= pht @ kt
    return kt.T @ y  # type: ignore[no-any-return]
