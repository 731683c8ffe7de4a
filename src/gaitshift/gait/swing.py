"""Swing-foot trajectories: smooth polynomials from lift-off to touchdown.

Horizontal position and yaw follow a quintic ("minimum-jerk") blend ``s(u) = 10u^3 - 15u^4 + 6u^5``,
u = (t - t0)/(t1 - t0) in [0, 1], with zero velocity and acceleration at both ends. Height follows the
sextic polynomial of paper 003 (§3.3) with seven conditions: z(0) = z0, z(1) = z1, zero velocity and
acceleration at both ends, and z(1/2) = max(z0, z1) + clearance (the apex).

Over terrain (:class:`EdgeClearance`) the horizontal blend runs in a window ``[a, b]`` of the swing,
``s((u - a) / (b - a))``, while the height keeps the whole swing: a foot climbing a stair rises before
it moves forward, one stepping down moves before it descends. The window is the widest (smallest
``a + 1 - b`` on a grid of :data:`WINDOW_STEP`) that keeps the sole ``margin`` above every terrain
break it passes over (a stair edge) while the break is within ``margin`` of the sole's toe or heel
(a foot that lags its reference by a few cm must not catch the edge with its heel as it sets down);
on flat ground it is [0, 1], the plain swing.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from gaitshift.models.arrays import BoolArray, FloatArray, FloatLike, Int8Array
from gaitshift.models.sextic import SEXTIC_INVERSE
from gaitshift.models.terrain import Terrain

#: grid of the swing window's delay and advance, fraction of the swing
WINDOW_STEP = 0.025
#: largest delay or advance of the horizontal blend, fraction of the swing
WINDOW_MAX = 0.45
#: samples of a swing checked against the terrain breaks
WINDOW_SAMPLES = 1001


def min_jerk(u: FloatArray) -> FloatArray:
    """Blend s(u) = 10u^3 - 15u^4 + 6u^5, shape of ``u``; s(0)=0, s(1)=1, s', s'' zero at both ends."""
    u = np.clip(u, 0.0, 1.0)
    return u**3 * (10.0 + u * (-15.0 + 6.0 * u))


def min_jerk_rates(u: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The first two derivatives of :func:`min_jerk` in u, ``s'(u) = 30 u^2 (1 - u)^2`` and
    ``s''(u) = 60 u (1 - u) (1 - 2u)``, shape of ``u``; 0 outside [0, 1] (the blend is held there)."""
    u = np.asarray(u, float)
    inside = (u >= 0.0) & (u <= 1.0)
    w = 1.0 - u
    return np.where(inside, 30.0 * u**2 * w**2, 0.0), np.where(inside, 60.0 * u * w * (1.0 - 2.0 * u), 0.0)


def sextic_height_coefficients(z0: FloatLike, z1: FloatLike, apex: FloatLike) -> FloatArray:
    """Coefficients a_0..a_6 (in u) of the sextic with z(0)=z0, z(1)=z1, z(1/2)=apex and zero
    velocity and acceleration at u=0 and u=1. Inputs broadcast; output shape (..., 7).

    With a_0 = z0 and a_1 = a_2 = 0, the remaining four coefficients solve the fixed 4x4 system of
    :mod:`gaitshift.models.sextic` (rhs ``[z1 - z0, 0, 0, apex - z0]``).
    """
    z0, z1, apex = np.broadcast_arrays(np.asarray(z0, float), np.asarray(z1, float), np.asarray(apex, float))
    # a3..a6 = M^-1 [z1 - z0, 0, 0, apex - z0]: only columns 0 and 3 of M^-1 matter
    a36 = (z1 - z0)[..., None] * SEXTIC_INVERSE[:, 0] + (apex - z0)[..., None] * SEXTIC_INVERSE[:, 3]
    zeros = np.zeros_like(z0)[..., None]
    return np.concatenate([z0[..., None], zeros, zeros, a36], axis=-1)


def swing_path(
    start: FloatArray, end: FloatArray, clearance: float, u: FloatArray, window: tuple[float, float] = (0.0, 1.0)
) -> FloatArray:
    """Foot position along a swing from ``start`` to ``end`` (each (3,) or (K, 3)) at phases ``u``.

    Args:
        start: lift-off sole position, m, shape (3,) or broadcastable to (len(u), 3).
        end: touchdown sole position, m, same shape rules.
        clearance: apex height above the higher of the two soles, m.
        u: normalised time in [0, 1], shape (K,).
        window: (a, b), the part of the swing in which the foot moves horizontally (module docstring).

    Returns:
        Positions, shape (K, 3).
    """
    u = np.clip(np.asarray(u, float), 0.0, 1.0)
    start = np.broadcast_to(np.asarray(start, float), (len(u), 3))
    end = np.broadcast_to(np.asarray(end, float), (len(u), 3))
    s = min_jerk((u - window[0]) / (window[1] - window[0]))[:, None]
    out = start + (end - start) * s
    apex = np.maximum(start[:, 2], end[:, 2]) + clearance
    coef = sextic_height_coefficients(start[:, 2], end[:, 2], apex)
    powers = u[:, None] ** np.arange(7)
    out[:, 2] = np.sum(coef * powers, axis=1)
    return out


@dataclass(frozen=True)
class EdgeClearance:
    """Swings over ``terrain``: soles ``sole_length`` m long (along x) kept ``margin`` m above the
    breaks they pass over, and ``margin`` m beyond toe and heel (module docstring)."""

    terrain: Terrain
    sole_length: float
    margin: float
    #: leave out the breaks under the lift-off and touchdown soles, lengthened by ``margin`` (a believed terrain whose
    #: edges moved by a cell after the footholds were chosen: the soles stand where they stand)
    skip_under_soles: bool = False

    def window(self, start: FloatArray, end: FloatArray, clearance: float) -> tuple[float, float]:
        """(a, b) of the swing from ``start`` to ``end`` (3,) m with apex ``clearance`` m above the
        higher sole; (0, 1) when no break lies between them.

        Raises:
            ValueError: no window on the grid clears the breaks (a higher swing is needed).
        """
        half = 0.5 * self.sole_length + self.margin  # the sole, lengthened by the margin at toe and heel
        lo, hi = sorted((float(start[0]), float(end[0])))
        b = self.terrain.breaks()
        b = b[(b > lo - half) & (b < hi + half)]
        if self.skip_under_soles:
            b = b[(np.abs(b - lo) >= half) & (np.abs(b - hi) >= half)]
        if len(b) == 0:
            return 0.0, 1.0
        top = np.maximum(self.terrain.height(b - 1e-9), self.terrain.height(b)) + self.margin  # (nb,)
        u = np.linspace(0.0, 1.0, WINDOW_SAMPLES)
        z = swing_path(start, end, clearance, u)[:, 2]  # the height does not depend on the window
        below = z < top.max()  # only where the sole is below a break's top can it touch one
        if not below.any():
            return 0.0, 1.0
        u, z = u[below], z[below]
        g = np.arange(0.0, WINDOW_MAX + 1e-9, WINDOW_STEP)
        x0, dx, n = float(start[0]), float(end[0]) - float(start[0]), len(g)
        for level in range(2 * n - 1):  # delay + advance in grid steps: the cheapest windows first
            i = np.arange(max(0, level - n + 1), min(level, n - 1) + 1)
            a, e = g[i], g[level - i]  # delay, advance
            x = x0 + dx * min_jerk((u[None, :] - a[:, None]) / (1.0 - e - a)[:, None])  # (m, n)
            over = np.abs(x[..., None] - b) < half  # (m, n, nb): a break under the sole
            ok = ~(over & (z[:, None] < top)).any(axis=(1, 2))
            if ok.any():  # the least a + e; among equal ones the least delay
                k = int(np.argmin(np.where(ok, a + e, np.inf)))
                return float(a[k]), float(1.0 - e[k])
        raise ValueError(
            f"a swing from x = {lo:.3f} to {hi:.3f} m cannot keep {self.margin} m above the edges at x = "
            f"{np.round(b, 3).tolist()} (raise swing_height)"
        )


def foot_yaws(contact: BoolArray, foot_pos: FloatArray, footsteps: FloatArray, side_of: Int8Array) -> FloatArray:
    """Yaw of each sole over a plan, (N, 2) rad, from its contact flags (N, 2), sole centres (N, 2, 3)
    and footholds (M, 4) x, y, z, yaw with their sides (M,).

    Each contact interval takes the yaw of the foothold (same side) nearest to the sole; each swing
    blends the yaws of the contacts around it with the minimum-jerk profile :func:`min_jerk` (the same
    blend as the swing position), the shorter way round.
    """
    n = len(contact)
    out = np.zeros((n, 2))
    for side in (0, 1):
        steps = footsteps[side_of == side]
        if len(steps) == 0:
            continue
        c = contact[:, side].astype(np.int8)
        bounds = np.concatenate([[0], np.flatnonzero(np.diff(c)) + 1, [n]])
        kinds = [bool(c[a]) for a in bounds[:-1]]
        yaws = [
            float(steps[np.argmin(np.linalg.norm(steps[:, :2] - foot_pos[a, side, :2], axis=1)), 3]) if k else math.nan
            for a, k in zip(bounds[:-1], kinds, strict=True)
        ]
        known = [y for y in yaws if not math.isnan(y)]
        default = known[0] if known else 0.0
        for i, (a, b) in enumerate(itertools.pairwise(bounds)):
            if kinds[i]:
                out[a:b, side] = yaws[i]
                continue
            before = next((yaws[j] for j in range(i - 1, -1, -1) if kinds[j]), None)
            after = next((yaws[j] for j in range(i + 1, len(yaws)) if kinds[j]), None)
            y0 = before if before is not None else (after if after is not None else default)
            y1 = after if after is not None else y0
            y1 = y0 + (y1 - y0 + math.pi) % (2 * math.pi) - math.pi
            u = (np.arange(a, b) - a + 1) / (b - a + 1)
            out[a:b, side] = y0 + (y1 - y0) * min_jerk(u)
    return out


def mid_heading(foot_yaw: FloatArray) -> FloatArray:
    """The heading between the two soles, (N,) rad: the left yaw plus half the (wrapped) difference."""
    d = (foot_yaw[:, 1] - foot_yaw[:, 0] + math.pi) % (2 * math.pi) - math.pi
    return np.asarray(foot_yaw[:, 0] + 0.5 * d, dtype=np.float64)
