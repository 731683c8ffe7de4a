"""Pieces of the invariant EKF's algebra (:mod:`gaitshift.control.estimation.inekf`): a writable view
of a matrix diagonal, the covariance's change when the positions' origin moves, the feet at their stance
points, and the buffers of a correction for one set of measured feet (its ``H^T`` rows as in the
filter's module docstring).

State order of the error xi (as in :mod:`gaitshift.control.estimation.inekf`): rotation (0:3), velocity
(3:6), position (6:9), the two contact points d_L, d_R (9:15), with flat feet their orientations Z_L,
Z_R (15:21), then the biases.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from gaitshift.control.estimation.lie import SKEW
from gaitshift.control.estimation.types import FootKinematics


def diagonal_view(a: np.ndarray) -> np.ndarray:
    """Writable view (n,) of the diagonal of a square C-contiguous array (n, n)."""
    n = a.shape[0]
    return np.lib.stride_tricks.as_strided(a, shape=(n,), strides=((n + 1) * a.itemsize,))


class StancePoints:
    """The point ``r_i`` of each stance sole the filter takes as still, in the sole frames
    (:mod:`~gaitshift.control.estimation.inekf`, "The stance point").

    Attributes:
        points: (2, 3) m, the requested ``r_i`` (zero: the sole centres).
        used: (2, 3) m, the ``r_i`` the filter's stored points stand for.
    """

    def __init__(self) -> None:
        self.points, self.used = np.zeros((2, 3)), np.zeros((2, 3))

    def reset(self) -> None:
        self.points[...] = self.used[...] = 0.0

    def place(self, cop: np.ndarray) -> None:
        """``cop`` (2, 2): x, y in the sole frames, m; a NaN row keeps that sole's point."""
        known = np.isfinite(cop).all(axis=1)
        self.points[known, 0:2] = cop[known]

    def apply(self, feet: FootKinematics, rot: np.ndarray, stored: np.ndarray, in_state: list[bool]) -> FootKinematics:
        """``feet`` with each sole's position at its stance point ``y_c + R_f r_i``; in place, the stored
        points ``stored`` (2, 3) of the soles ``in_state`` moved by ``R R_f (r_i - r_used)`` (``rot``: R)."""
        if not (self.points.any() or self.used.any()):
            return feet
        moved = np.einsum("sij,sj->si", feet.rot, self.points - self.used)
        for i in (0, 1):
            if in_state[i]:
                stored[i] += rot @ moved[i]
        self.used[...] = self.points
        return replace(feet, pos=feet.pos + np.einsum("sij,sj->si", feet.rot, self.points))


def move_origin(cov: np.ndarray, c: np.ndarray) -> None:
    """In place: the covariance of the error when the positions' origin moves by ``c`` (3,) m,
    ``P <- T P T^T`` with ``T = I + [-c^ in the (p, R), (d_L, R), (d_R, R) blocks]`` (rows 6:15 are
    p, d_L, d_R; rows 0:3 the rotation; module docstring)."""
    neg_skew = (c @ SKEW).reshape(3, 3).T  # (c @ SKEW) is c^ row-major; its transpose is -c^
    rows = cov[0:3, :]
    for j in (6, 9, 12):
        cov[j : j + 3, :] += neg_skew @ rows
    cols = cov[:, 0:3]
    for j in (6, 9, 12):
        cov[:, j : j + 3] += cols @ neg_skew.T


class CorrectionPattern:
    """Buffers of the correction for one set of measured feet: position rows (3 per foot), then,
    with flat feet, orientation rows (3 per foot)."""

    def __init__(self, measured: tuple[bool, bool], nx: int, flat: bool):
        feet = [i for i in (0, 1) if measured[i]]
        m = 3 * len(feet)
        n = 2 * m if flat else m
        self.ht = np.zeros((nx, n))  # H^T
        for col, i in enumerate(feet):
            for k in range(3):
                self.ht[6 + k, 3 * col + k] = -1.0  # -xi_p
                self.ht[9 + 3 * i + k, 3 * col + k] = 1.0  # +xi_di
                if flat:
                    self.ht[k, m + 3 * col + k] = -1.0  # -xi_R
                    self.ht[15 + 3 * i + k, m + 3 * col + k] = 1.0  # +xi_Zi
        self.h = np.ascontiguousarray(self.ht.T)
        self.feet = feet
        self.rows = slice(3 * feet[0], 3 * feet[-1] + 3)  # rows of a (6,) two-foot vector
        pos_rep = np.repeat(feet, 3)
        self.rep = np.concatenate([pos_rep, pos_rep + 2]) if flat else pos_rep  # index into [var, rot_var]
        self.s = np.zeros((n, n))
        self.s_diag = diagonal_view(self.s)
        self.noise = np.zeros(n)  # measurement variances of these rows (set by the filter)
