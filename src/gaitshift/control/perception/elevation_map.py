"""The controller's elevation map: a robot-centred grid of ground heights with their variances.

The map is ``n x n`` square cells of side ``resolution`` m, aligned with the world axes, on the world's
lattice (cell ``(i, j)`` covers ``[i r, (i + 1) r) x [j r, (j + 1) r)``), its corner moved with the
robot (:meth:`ElevationMap.recenter`: the cells that stay keep their estimate, the new ones are
unknown). Each cell holds a height ``h`` (m) and its variance ``P`` (m^2; ``inf``: never seen).

A frame of points ``z_k`` (world frame, from the *estimated* camera pose: the map carries the
estimator's drift) with variances ``R_k`` is fused per cell as one Kalman update of a constant
(Fankhauser et al. 2014, "Robot-centric elevation mapping", eq. (2)), all points of a cell at once:

.. math::

    W = \\sum_k R_k^{-1}, \\quad Z = \\sum_k R_k^{-1} z_k, \\qquad
    P^+ = (P^{-1} + W)^{-1}, \\quad h^+ = P^+ (P^{-1} h + Z)                      (1)

and between frames every known cell's variance grows by ``process_noise`` m^2/s (the robot's pose
drifts, the world may change):

.. math:: P \\leftarrow P + q\\, \\Delta t                                          (2)

An *edge* is a known cell whose height differs from a known 4-neighbour's by more than a step
(:meth:`ElevationMap.edges`): a stair's nosing, a block's side. Vectorised over points and cells
(``np.bincount``); nothing here reads the world: the points are what the robot's camera reported.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["EDGE_STEP", "ElevationMap", "MapSettings", "seen_cells", "step_edges"]

#: the step between neighbour cells that the map's pictures (figure, browser view, Rerun) mark as an edge, m
EDGE_STEP = 0.04
#: the colour (RGB) the map's pictures draw its edge cells in (browser view, Rerun)
EDGE_COLOR = (255, 0, 0)


@dataclass(frozen=True)
class MapSettings:
    """The map's size (m, side of the square), ``resolution`` (m per cell) and ``process_noise``
    (m^2/s, eq. (2))."""

    size: float = 4.0
    resolution: float = 0.04
    process_noise: float = 1e-4


class ElevationMap:
    """The map (module docstring). ``height`` and ``variance`` are (n, n) arrays indexed [i - i0, j - j0]
    with ``(i0, j0)`` = :attr:`corner`, the lattice index of cell [0, 0]."""

    def __init__(self, settings: MapSettings | None = None) -> None:
        self.settings = s = settings or MapSettings()
        self.n = max(2, round(s.size / s.resolution))
        self.height = np.zeros((self.n, self.n))
        self.variance = np.full((self.n, self.n), np.inf)
        self.corner = np.zeros(2, dtype=np.int64)

    def snapshot(self) -> ElevationMap:
        """A copy of the map as it is now, that later frames do not change (a background re-plan's map)."""
        out = ElevationMap(self.settings)
        out.height, out.variance, out.corner = self.height.copy(), self.variance.copy(), self.corner.copy()
        return out

    @property
    def known(self) -> np.ndarray:
        """(n, n) bool: cells that have been seen."""
        out: np.ndarray = np.isfinite(self.variance)
        return out

    def cells(self, xy: np.ndarray) -> np.ndarray:
        """Lattice indices (K, 2) int of world points ``xy`` (K, 2) m."""
        return np.floor(np.asarray(xy, dtype=float)[..., :2] / self.settings.resolution).astype(np.int64)

    def centres(self) -> np.ndarray:
        """World xy (n, n, 2) m of every cell's centre."""
        r = self.settings.resolution
        i = (self.corner[0] + np.arange(self.n) + 0.5) * r
        j = (self.corner[1] + np.arange(self.n) + 0.5) * r
        return np.stack(np.meshgrid(i, j, indexing="ij"), axis=-1)

    def recenter(self, xy: np.ndarray) -> None:
        """Move the grid so that the world point ``xy`` (2,) m lies in its middle cell; cells that stay
        in the grid keep their estimate, the others become unknown."""
        corner = self.cells(np.asarray(xy, dtype=float)[None, :2])[0] - self.n // 2
        shift = corner - self.corner
        if not np.any(shift):
            return
        h, p = np.zeros_like(self.height), np.full_like(self.variance, np.inf)
        a0, a1 = np.maximum(shift, 0), np.minimum(self.n + shift, self.n)  # old indices kept
        if np.all(a1 > a0):
            b0, b1 = a0 - shift, a1 - shift
            h[b0[0] : b1[0], b0[1] : b1[1]] = self.height[a0[0] : a1[0], a0[1] : a1[1]]
            p[b0[0] : b1[0], b0[1] : b1[1]] = self.variance[a0[0] : a1[0], a0[1] : a1[1]]
        self.height, self.variance, self.corner = h, p, corner

    def age(self, dt: float) -> None:
        """Eq. (2) over ``dt`` s."""
        self.variance += self.settings.process_noise * dt

    def fuse(self, points: np.ndarray, variance: np.ndarray) -> int:
        """Eq. (1): fuse world points (M, 3) m with height variances (M,) m^2; returns the number of
        points that fell inside the grid."""
        idx = self.cells(points) - self.corner
        inside = np.all((idx >= 0) & (idx < self.n), axis=1) & (variance > 0)
        flat = idx[inside, 0] * self.n + idx[inside, 1]
        w = 1.0 / variance[inside]
        size = self.n * self.n
        big_w = np.bincount(flat, weights=w, minlength=size).reshape(self.n, self.n)
        big_z = np.bincount(flat, weights=w * points[inside, 2], minlength=size).reshape(self.n, self.n)
        seen = big_w > 0
        prior_info = 1.0 / self.variance[seen]  # 0 for an unknown cell
        post = 1.0 / (prior_info + big_w[seen])
        self.height[seen] = post * (prior_info * self.height[seen] + big_z[seen])
        self.variance[seen] = post
        return int(np.count_nonzero(inside))

    def lookup(self, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Height (K,) m and variance (K,) m^2 at world points ``xy`` (K, 2) (``inf`` variance and
        height 0 outside the grid or where unseen)."""
        idx = self.cells(np.atleast_2d(xy)) - self.corner
        inside = np.all((idx >= 0) & (idx < self.n), axis=1)
        h = np.zeros(len(idx))
        p = np.full(len(idx), np.inf)
        i, j = idx[inside, 0], idx[inside, 1]
        h[inside], p[inside] = self.height[i, j], self.variance[i, j]
        return h, p

    def edges(self, step: float) -> np.ndarray:
        """(n, n) bool: known cells whose height differs by more than ``step`` m from a known
        4-neighbour's (:func:`step_edges`)."""
        return step_edges(self.height, self.known, step)


def step_edges(height: np.ndarray, known: np.ndarray, step: float) -> np.ndarray:
    """(n, m) bool: the ``known`` cells of the grid ``height`` (m) whose height differs by more than
    ``step`` m from a known 4-neighbour's."""
    out = np.zeros_like(known, dtype=bool)
    for axis in (0, 1):
        a = [slice(None), slice(None)]
        b = [slice(None), slice(None)]
        a[axis], b[axis] = slice(1, None), slice(None, -1)
        jump = known[tuple(a)] & known[tuple(b)] & (np.abs(height[tuple(a)] - height[tuple(b)]) > step)
        out[tuple(a)] |= jump
        out[tuple(b)] |= jump
    return out


def seen_cells(
    height: np.ndarray, known: np.ndarray, corner: np.ndarray, resolution: float, step: float = EDGE_STEP
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A map's seen cells as a picture needs them: their centres at their heights (N, 3) m (row-major
    order of the grid ``height`` (n, m), its cell [0, 0]'s lower corner at world xy ``corner``), each
    height scaled to [0, 1] over the seen range (N,), and whether each is on an edge (N,) bool
    (:func:`step_edges` with ``step`` m)."""
    ij = np.argwhere(known)
    h = height[known]
    points = np.column_stack([np.asarray(corner, dtype=float) + (ij + 0.5) * resolution, h])
    lo = float(h.min()) if len(h) else 0.0
    span = max(float(h.max()) - lo, 1e-3) if len(h) else 1.0
    return points, (h - lo) / span, step_edges(height, known, step)[known]
