"""Terrain: the ground height z(x) as a floor at z = 0 with pieces on it (treads, steps, ramps).

A piece spans ``x0 <= x < x1`` (m) across the whole width (every y) and its top goes linearly from
``z0`` at ``x0`` to ``z1`` at ``x1`` (m): ``z0 = z1`` is a flat tread or step, ``z0 != z1`` a ramp
of slope ``(z1 - z0) / (x1 - x0)`` (pitch ``atan`` of it, rad). Pieces are sorted and disjoint;
outside them the ground is the floor, z = 0. Between pieces the height may jump (a stair edge).

A *break* is an x where the height or the slope changes (a stair edge, the foot of a ramp): a flat
sole cannot rest across one, so a foothold's sole must lie between two breaks
(:meth:`Terrain.sole_fits`). The simulator builds one box per piece
(:mod:`gaitshift.sim.terrain_geoms`); planners only need :meth:`Terrain.height`.

A flat piece may carry a field of random blocks (:class:`gaitshift.models.blocks.Blocks`): a 2-D
ground. Its profile :meth:`Terrain.height` is the field's mean (the piece's top); the ground at a
point of the plane is :meth:`Terrain.height_xy`, and :meth:`Terrain.edge_distance` measures a sole's
room from every step edge in the plane (the stairs' and the blocks'). Only the world and its metrics
read those: a planner told such a terrain would plan on its mean, so it is not told
(:func:`gaitshift.control.drivers.prepare`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property, lru_cache
from typing import Any

import numpy as np

from gaitshift.models.arrays import FloatArray, FloatLike
from gaitshift.models.blocks import Blocks

__all__ = ["EDGE_MIN_STEP", "FLAT", "Piece", "Terrain"]

#: m, the least height difference across a line that :meth:`Terrain.edge_distance` counts as a step edge:
#: the controller's own (``BeliefSettings.jump``, the height change its profile cuts at); a sole across a
#: smaller step lies within the level patch's tolerance (control/perception/patches.py)
EDGE_MIN_STEP = 0.02


@dataclass(frozen=True)
class Piece:
    """One piece of terrain: x from ``x0`` to ``x1`` (m), top height ``z0`` at x0 to ``z1`` at x1 (m);
    ``blocks``: a field of random blocks on it (a flat piece only; module docstring)."""

    x0: float
    x1: float
    z0: float
    z1: float
    blocks: Blocks | None = None

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
            if a.blocks is not None and a.z0 != a.z1:
                raise ValueError(f"terrain piece x = [{a.x0}, {a.x1}]: blocks need a flat piece (z0 = z1)")
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

    @property
    def blocks(self) -> tuple[Piece, ...]:
        """The pieces that carry a field of blocks (a 2-D ground)."""
        return tuple(p for p in self.pieces if p.blocks is not None)

    def height_xy(self, x: FloatLike, y: FloatLike) -> FloatArray:
        """Ground height z(x, y), m (broadcast shape of ``x`` and ``y``): :meth:`height` plus the blocks'
        offsets (eq. (1) of :mod:`gaitshift.models.blocks`)."""
        x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        z = self.height(x)
        for p in self.blocks:
            z = z + p.blocks.offset(p.x0, p.x1, x, y)  # type: ignore[union-attr]
        return np.asarray(z, float)

    def edge_distance(
        self, x: FloatLike, y: FloatLike, half_x: float, half_y: float, min_step: float = EDGE_MIN_STEP
    ) -> FloatArray:
        """Signed distance (m, broadcast shape of ``x``, ``y``) from an axis-aligned sole (centre ``x``, ``y``,
        half extents ``half_x``, ``half_y`` m) to the nearest step edge in the plane: a stair edge
        (:meth:`steps`, a line across every y) or a block's side (:meth:`Blocks.sides`) where the ground
        either side differs by more than ``min_step`` m; negative when the sole lies across one; ``inf``
        without step edges."""
        x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        xl, yl = self._edge_segments(min_step)
        return np.asarray(np.minimum(_to_lines(xl, x, y, half_x, half_y), _to_lines(yl, y, x, half_y, half_x)), float)

    @lru_cache(maxsize=4)  # noqa: B019 (the terrain is frozen and hashable)
    def _edge_segments(self, min_step: float) -> tuple[FloatArray, FloatArray]:
        """The step edges of :meth:`edge_distance` as segments ``[u, v_a, v_b]`` along x and along y."""
        eps = 1e-7
        steps = self.steps()
        steps = steps[np.abs(self.height(steps - eps) - self.height(steps)) > min_step]
        xl = [np.column_stack([steps, np.full(len(steps), -np.inf), np.full(len(steps), np.inf)])]
        yl = [np.zeros((0, 3))]
        for p in self.blocks:
            sx, sy = p.blocks.sides(p.x0, p.x1)  # type: ignore[union-attr]
            mid = 0.5 * (sx[:, 1] + sx[:, 2])
            xl.append(sx[np.abs(self.height_xy(sx[:, 0] - eps, mid) - self.height_xy(sx[:, 0] + eps, mid)) > min_step])
            mid = 0.5 * (sy[:, 1] + sy[:, 2])
            yl.append(sy[np.abs(self.height_xy(mid, sy[:, 0] - eps) - self.height_xy(mid, sy[:, 0] + eps)) > min_step])
        if self.blocks:  # a profile step at a field's end is the blocks' sides there, not a line across every y
            ends = np.array([v for p in self.blocks for v in (p.x0, p.x1)])
            at_end = np.isclose(xl[0][:, 0][:, None], ends[None, :])  # (S, E)
            beside = [[u, v, w] for u in xl[0][at_end.any(axis=1), 0] for v, w in self._beside_fields(u)]
            xl[0] = np.vstack([xl[0][~at_end.any(axis=1)], np.reshape(beside, (-1, 3))])
        return np.vstack(xl), np.vstack(yl)

    def _beside_fields(self, x: float) -> list[tuple[float, float]]:
        """The spans of y (m) beside the fields of blocks that end at ``x``: there the profile's step runs."""
        w = [p.blocks.half_width for p in self.blocks if np.isclose(x, [p.x0, p.x1]).any()]  # type: ignore[union-attr]
        return [(-np.inf, -w[0]), (w[0], np.inf)] if w else [(-np.inf, np.inf)]

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
        return cls(tuple(Piece(float(r[0]), float(r[1]), float(r[2]), float(r[3])) for r in (rows or ())))


def _to_lines(seg: FloatArray, u: FloatArray, v: FloatArray, hu: float, hv: float) -> FloatArray:
    """Signed distance (shape of ``u``) from rectangles (centre ``u``, ``v``; half extents ``hu``, ``hv``)
    to the nearest of the segments ``seg`` (S, 3) rows ``[u_s, v_a, v_b]`` (the line u = u_s from v_a to
    v_b): the gap along u where the spans in v overlap (negative: across), else the corner distance."""
    if not len(seg):
        return np.full(u.shape, np.inf)
    across = np.abs(u[..., None] - seg[:, 0]) - hu  # (..., S)
    off = np.maximum(np.maximum(seg[:, 1] - (v[..., None] + hv), (v[..., None] - hv) - seg[:, 2]), 0.0)
    return np.asarray(np.where(off > 0, np.hypot(np.maximum(across, 0.0), off), across).min(axis=-1), float)


#: the floor alone
FLAT = Terrain()
