"""Terrain: the ground height z(x) as a floor at z = 0 with pieces on it (treads, steps, ramps).

A piece spans ``x0 <= x < x1`` (m) across the whole width (every y) and its top goes linearly from
``z0`` at ``x0`` to ``z1`` at ``x1`` (m): ``z0 = z1`` is a flat tread or step, ``z0 != z1`` a ramp
of slope ``(z1 - z0) / (x1 - x0)`` (pitch ``atan`` of it, rad). Pieces are sorted and disjoint;
outside them the ground is the floor, z = 0. Between pieces the height may jump (a stair edge).

A *break* is an x where the height or the slope changes (a stair edge, the foot of a ramp): a flat
sole cannot rest across one, so a foothold's sole must lie between two breaks
(:meth:`Terrain.sole_fits`). The simulator builds one box per piece
(:mod:`gaitshift.sim.terrain_geoms`); planners only need :meth:`Terrain.height`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from gaitshift.models.arrays import FloatArray, FloatLike

__all__ = ["FLAT", "Piece", "Terrain"]


@dataclass(frozen=True)
class Piece:
    """One piece of terrain: x from ``x0`` to ``x1`` (m), top height ``z0`` at x0 to ``z1`` at x1 (m)."""

    x0: float
    x1: float
    z0: float
    z1: float

    @property
    def slope(self) -> float:
        """dz/dx of the top, dimensionless."""
        return (self.z1 - self.z0) / (self.x1 - self.x0)

    @property
    def pitch(self) -> float:
        """Inclination of the top about +y, rad (positive: rising along +x)."""
        return math.atan(self.slope)


@dataclass(frozen=True)
class Terrain:
    """The ground (module docstring): ``pieces`` sorted by x, disjoint. Hashable (a cache key)."""

    pieces: tuple[Piece, ...] = ()

    def __post_init__(self) -> None:
        for a in self.pieces:
            if not a.x1 > a.x0:
                raise ValueError(f"terrain piece x = [{a.x0}, {a.x1}]: x1 must exceed x0")
        for a, b in zip(self.pieces, self.pieces[1:], strict=False):
            if b.x0 < a.x1:
                raise ValueError(f"terrain pieces overlap or are unsorted: x = [{a.x0}, {a.x1}] and [{b.x0}, {b.x1}]")

    @property
    def flat(self) -> bool:
        """No pieces: the floor only."""
        return not self.pieces

    def _columns(self) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        p = self.pieces
        return tuple(np.array([getattr(q, k) for q in p], float) for k in ("x0", "x1", "z0", "z1"))  # type: ignore[return-value]

    def _piece_at(self, x: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Height and slope of the piece under each x (shape of ``x``; 0 and 0 on the floor)."""
        if self.flat:
            return np.zeros_like(x), np.zeros_like(x)
        x0, x1, z0, z1 = self._columns()
        k = np.clip(np.searchsorted(x0, x, side="right") - 1, 0, len(x0) - 1)
        inside = (x >= x0[k]) & (x < x1[k])
        slope = (z1[k] - z0[k]) / (x1[k] - x0[k])
        return np.where(inside, z0[k] + slope * (x - x0[k]), 0.0), np.where(inside, slope, 0.0)

    def height(self, x: FloatLike) -> FloatArray:
        """Ground height z(x), m, shape of ``x``."""
        return np.asarray(self._piece_at(np.asarray(x, float))[0], float)

    def slope(self, x: FloatLike) -> FloatArray:
        """dz/dx of the ground at x, shape of ``x`` (0 on the floor)."""
        return np.asarray(self._piece_at(np.asarray(x, float))[1], float)

    def breaks(self) -> FloatArray:
        """The x of every break (height or slope changes there), sorted, m."""
        return self._breaks.copy()

    @cached_property
    def _breaks(self) -> FloatArray:
        xs = np.unique(np.array([v for q in self.pieces for v in (q.x0, q.x1)], float))
        eps = 1e-9
        h0, s0 = self._piece_at(xs - eps)
        h1, s1 = self._piece_at(xs)
        return np.asarray(xs[(np.abs(h0 - h1) > 1e-7) | (np.abs(s0 - s1) > 1e-7)], float)

    def steps(self) -> FloatArray:
        """The x of every break where the height jumps (a stair or step edge, not a ramp's kink), m."""
        b = self._breaks
        return np.asarray(b[np.abs(self.height(b - 1e-9) - self.height(b)) > 1e-7], float)

    def sole_fits(self, x: float, yaw: float, length: float, width: float) -> float | None:
        """None if a sole (centre x m, yaw rad, ``length`` x ``width`` m) lies between two breaks;
        else the x of the break under it."""
        half = 0.5 * (length * abs(math.cos(yaw)) + width * abs(math.sin(yaw)))
        b = self.breaks()
        under = b[(b > x - half) & (b < x + half)]
        return float(under[0]) if len(under) else None

    def clamp_sole(self, x: float, target: float, half: float, margin: float = 0.0) -> float:
        """``target`` (m) clipped so that a sole of half length ``half`` (m) stays between the two breaks
        around ``x`` (the piece of ground under the planned foothold ``x``), and ``margin`` (m) more from
        a break that is a step in height (a stair or step edge; not a ramp's kink), both margins shrunk
        alike where the piece leaves no room for them; ``target`` when the gap is shorter than the sole."""
        b = self.breaks()
        below, above = b[b <= x], b[b > x]
        lo = float(below.max()) + half if len(below) else -math.inf
        hi = float(above.min()) - half if len(above) else math.inf
        if lo > hi:
            return target
        m_lo = max(margin, 0.0) if len(below) and self.is_step(float(below.max())) else 0.0
        m_hi = max(margin, 0.0) if len(above) and self.is_step(float(above.min())) else 0.0
        if m_lo + m_hi > hi - lo:
            scale = (hi - lo) / (m_lo + m_hi)
            m_lo, m_hi = m_lo * scale, m_hi * scale
        return min(max(target, lo + m_lo), hi - m_hi)

    def is_step(self, x: float) -> bool:
        """Whether the ground's height jumps at ``x`` (m)."""
        return abs(float(self.height(x - 1e-9)) - float(self.height(x))) > 1e-7

    def as_list(self) -> list[list[float]]:
        """``[[x0, x1, z0, z1], ...]`` (the trajectory's ``meta["terrain"]``)."""
        return [[q.x0, q.x1, q.z0, q.z1] for q in self.pieces]

    @classmethod
    def from_list(cls, rows: Any) -> Terrain:
        """The terrain of :meth:`as_list` rows (None or empty: flat)."""
        return cls(tuple(Piece(*(float(v) for v in r)) for r in (rows or ())))


#: the floor alone
FLAT = Terrain()
