"""A field of random blocks on a flat piece of terrain: a 2-D ground (issue 29).

A flat piece ``x0 <= x < x1`` at top height ``z`` (:class:`gaitshift.models.terrain.Piece`) with
``blocks`` is, within ``|y| <= half_width``, a grid of square blocks of side ``size`` (m), block
``(i, j)`` covering

.. math::

    x_0 + i\\,s \\le x < \\min(x_0 + (i + 1)\\,s,\\ x_1), \\qquad
    -w + j\\,s \\le y < \\min(-w + (j + 1)\\,s,\\ w)                                    (1)

with its top at :math:`z + \\delta_{ij}`, :math:`\\delta_{ij} \\sim U(-h, h)` drawn once from
``numpy.random.default_rng(seed)`` in the grid's row-major order (``h`` = ``height``). Beyond
``|y| > w`` the piece is its flat top ``z``. The offsets have mean zero, so the piece's profile
height ``z`` (what :meth:`Terrain.height` says along the path) is the field's mean; the height at a
point of the plane is :meth:`Blocks.offset` added to it.

A block's side is a step edge where the tops either side of it differ (a sole across one does not
lie flat): between two blocks, and on the field's outline between a block and the ground around.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from gaitshift.models.arrays import FloatArray, FloatLike

__all__ = ["Blocks"]


@dataclass(frozen=True)
class Blocks:
    """Eq. (1): blocks of side ``size`` m, tops ``+- height`` m about the piece's, drawn from ``seed``,
    over ``|y| <= half_width`` m. Hashable (the plant's cache key holds the terrain)."""

    size: float
    height: float
    seed: int
    half_width: float = 1.0

    def __post_init__(self) -> None:
        if not (self.size > 0 and self.half_width > 0 and self.height >= 0 and self.seed >= 0):
            raise ValueError(f"blocks: size and half_width > 0, height and seed >= 0 (got {self})")

    def shape(self, x0: float, x1: float) -> tuple[int, int]:
        """(nx, ny): blocks along x over ``[x0, x1)`` and along y over ``[-w, w]``."""
        return math.ceil((x1 - x0) / self.size - 1e-9), math.ceil(2 * self.half_width / self.size - 1e-9)

    def offsets(self, x0: float, x1: float) -> FloatArray:
        """(nx, ny) m: each block's top relative to the piece's (eq. (1)); read-only."""
        return _draw(self.seed, self.height, *self.shape(x0, x1))

    def lines(self, x0: float, x1: float) -> tuple[FloatArray, FloatArray]:
        """The grid's lines of eq. (1): x (nx + 1,) over ``[x0, x1]`` and y (ny + 1,) over ``[-w, w]``, m."""
        nx, ny = self.shape(x0, x1)
        xs = np.minimum(x0 + self.size * np.arange(nx + 1), x1)
        return xs, np.minimum(-self.half_width + self.size * np.arange(ny + 1), self.half_width)

    def cells(self, x0: float, x1: float) -> FloatArray:
        """(nx * ny, 5) rows ``[xa, xb, ya, yb, dz]``: each block's extent (m) and offset (m), eq. (1)."""
        nx, ny = self.shape(x0, x1)
        xs, ys = self.lines(x0, x1)
        i, j = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")
        dz = self.offsets(x0, x1)
        return np.column_stack([xs[i].ravel(), xs[i + 1].ravel(), ys[j].ravel(), ys[j + 1].ravel(), dz.ravel()])

    def offset(self, x0: float, x1: float, x: FloatLike, y: FloatLike) -> FloatArray:
        """The top's offset (m) at points ``(x, y)`` (broadcast shapes): eq. (1) inside the field, 0
        outside it (beyond ``|y| > w`` or outside ``[x0, x1)``)."""
        x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        nx, ny = self.shape(x0, x1)
        i = np.floor((x - x0) / self.size).astype(int)
        j = np.floor((y + self.half_width) / self.size).astype(int)
        inside = (x >= x0) & (x < x1) & (y >= -self.half_width) & (y <= self.half_width)
        i, j = np.clip(i, 0, nx - 1), np.clip(j, 0, ny - 1)
        return np.where(inside, self.offsets(x0, x1)[i, j], 0.0)

    def sides(self, x0: float, x1: float) -> tuple[FloatArray, FloatArray]:
        """Every block's sides as segments: ``(xl, yl)``, xl (nx + 1) * ny rows ``[x, ya, yb]`` (sides of
        constant x, from ya to yb) and yl (ny + 1) * nx rows ``[y, xa, xb]`` (m). Whether a side is a step
        edge depends on the ground either side (:meth:`Terrain.edge_distance`)."""
        nx, ny = self.shape(x0, x1)
        xs, ys = self.lines(x0, x1)
        i, j = np.meshgrid(np.arange(nx + 1), np.arange(ny), indexing="ij")
        xl = np.column_stack([xs[i].ravel(), ys[j].ravel(), ys[j + 1].ravel()])
        i, j = np.meshgrid(np.arange(nx), np.arange(ny + 1), indexing="ij")
        yl = np.column_stack([ys[j].ravel(), xs[i].ravel(), xs[i + 1].ravel()])
        return xl, yl


@lru_cache(maxsize=64)
def _draw(seed: int, height: float, nx: int, ny: int) -> FloatArray:
    """Eq. (1)'s offsets (nx, ny), drawn row-major from ``default_rng(seed)``."""
    out = np.random.default_rng(seed).uniform(-height, height, size=(nx, ny))
    out.flags.writeable = False
    return np.asarray(out, float)
