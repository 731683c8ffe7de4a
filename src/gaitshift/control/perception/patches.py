"""Footholds on the 2-D map: the level patch nearest a planned foothold (a field of blocks, issue 29).

The belief of :mod:`gaitshift.control.perception.terrain_belief` is a profile z(x) along the path: it
cannot tell the left foot's block from the right foot's. This module reads the map
(:class:`~gaitshift.control.perception.elevation_map.ElevationMap`) in the plane. A sole centred at
:math:`c` (its extent along the world axes, half of the rotated sole's bounding box, grown by the edge
margin :math:`m`: the rectangle :math:`R(c)`) stands on a *level patch* when the heights :math:`h_i` of
the map cells :math:`i` that :math:`R(c)` overlaps lie, but for twice each cell's own standard
deviation :math:`\\sigma_i = \\sqrt{P_i}`, within :math:`\\tau` of the ground the profile believes in
there, a plane of the profile's slope :math:`s` along x (0 on a tread, the ramp's on a ramp) through
their median :math:`a`, and every cell is seen to :math:`\\sigma_i \\le \\sigma_{max}`:

.. math::

    a = \\operatorname{median}_i (h_i - s\\,\\Delta x_i), \\qquad
    |h_i - a - s\\,\\Delta x_i| - 2 \\sigma_i \\le \\tau, \\qquad
    \\sigma_i \\le \\sigma_{max} \\quad \\forall i \\in R(c)                              (1)

so no step edge higher than about :math:`\\tau` (more where the map is less sure) lies under the sole
or within :math:`m` of it; a cell across a block's side holds a height between the two tops, off
like one. Its height is :math:`a`. A fitted plane would not do: it explains a step under the sole as a
slope, leaving residuals of a quarter of the step (1 cm for 4 cm) that the map's noise hides; on 12
block walks it crossed 3 where eq. (1) crossed 10.

:func:`level_patch` judges the planned centre first, on the cells seen there: a *step is seen* when
the left side of eq. (1) fails on them (however unsure they are, a foothold is not moved on noise
alone). With no step seen it returns the planned centre at height :math:`a` when at least ``min_seen``
of its cells are seen (else None: the map cannot say). With a step seen it returns the centre on the
map's lattice within ``reach`` (m along x and y) where eq. (1) holds whole, nearest the planned one
(the distance along y weighted by ``lateral_cost``: a sideways move costs the balance more than a
shorter or longer stride), or None. Vectorised over the candidates
(:func:`numpy.lib.stride_tricks.sliding_window_view`). Nothing here reads the world.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from gaitshift.control.perception.elevation_map import ElevationMap

__all__ = ["Patch", "PatchRules", "level_patch"]


@dataclass(frozen=True)
class PatchRules:
    """Eq. (1)'s constants: the sole ``length`` and ``width`` (m), ``margin`` (m kept from an edge),
    ``flat_tol`` (tau, m), ``max_std`` (sigma_max, m), ``reach`` (m, the
    farthest move along x and y), ``lateral_cost`` (the weight of a move along y against one along x)
    and ``min_seen`` (the share of a planned patch's cells that must be seen for the map to decide)."""

    length: float
    width: float
    margin: float
    flat_tol: float = 0.01
    max_std: float = 0.012
    reach: tuple[float, float] = (0.2, 0.08)
    lateral_cost: float = 2.0
    min_seen: float = 0.5


@dataclass(frozen=True)
class Patch:
    """A level patch (eq. (1)): the sole centre ``x``, ``y`` m, its height ``z`` m (a), whether
    it was ``moved`` from the planned centre (a step seen there), and the ``room`` (x_lo, x_hi, y_lo,
    y_hi) m within which the centre may move and eq. (1) still hold (the run of such lattice centres
    through it along x and along y, within reach): where a step correction may put the sole."""

    x: float
    y: float
    z: float
    moved: bool
    room: tuple[float, float, float, float]


def level_patch(
    emap: ElevationMap, x: float, y: float, yaw: float, rules: PatchRules, slope: float = 0.0
) -> Patch | None:
    """The level patch (eq. (1), module docstring) for a sole planned at ``(x, y)`` m, ``yaw`` rad, on ground
    the profile believes of ``slope`` (dz/dx) there; None when the map cannot say (the planned place
    mostly unseen, nothing level within reach)."""
    c, s = abs(math.cos(yaw)), abs(math.sin(yaw))
    sole = (0.5 * (rules.length * c + rules.width * s), 0.5 * (rules.length * s + rules.width * c))
    half = (sole[0] + rules.margin, sole[1] + rules.margin)
    here = _fit_here(emap, x, y, half, slope)
    if here is None:
        return None
    z, dev, seen = here
    step = bool(np.any(dev > rules.flat_tol))  # a step seen where it was planned
    if not step and seen < rules.min_seen:
        return None
    grid = _level_grid(emap, x, y, half, rules, slope)
    if not step:
        room = (x, x, y, y) if grid is None else _room(grid[0], grid[1], grid[2], _centre(grid[0]))
        return Patch(x, y, z, False, (min(room[0], x), max(room[1], x), min(room[2], y), max(room[3], y)))
    if grid is None or not grid[0].any():
        return None
    ok, cx, cy, cz = grid
    cost = np.where(ok, np.hypot(cx - x, rules.lateral_cost * (cy - y)), np.inf)
    k = np.unravel_index(int(np.argmin(cost)), cost.shape)
    room = _room(ok, cx, cy, (int(k[0]), int(k[1])))
    return Patch(float(cx[k]), float(cy[k]), float(cz[k]), True, room)


def _window(emap: ElevationMap, x: float, y: float, half: tuple[float, float]) -> tuple[slice, slice] | None:
    """The map's cells that the rectangle ``half`` (m, x and y) about ``(x, y)`` overlaps, or None when it
    leaves the map."""
    lo = emap.cells(np.array([x - half[0], y - half[1]])) - emap.corner
    hi = emap.cells(np.array([x + half[0], y + half[1]])) - emap.corner
    if np.any(lo < 0) or np.any(hi >= emap.n) or np.any(hi < lo):
        return None
    return slice(int(lo[0]), int(hi[0]) + 1), slice(int(lo[1]), int(hi[1]) + 1)


def _fit_here(
    emap: ElevationMap, x: float, y: float, half: tuple[float, float], slope: float
) -> tuple[float, np.ndarray, float] | None:
    """Eq. (1) on the seen cells about ``(x, y)``: the height ``a`` m, each seen cell's deviation m (the
    left side before tau) and the share of the cells seen; None when the rectangle leaves the map or no
    cell is seen."""
    cells = _window(emap, x, y, half)
    if cells is None:
        return None
    std = np.sqrt(emap.variance[cells]).ravel()
    seen = np.isfinite(std)
    if not seen.any():
        return None
    r, i = emap.settings.resolution, np.arange(cells[0].start, cells[0].stop)
    dx = np.repeat((emap.corner[0] + i + 0.5) * r - x, cells[1].stop - cells[1].start)  # each cell's x from x
    level = emap.height[cells].ravel()[seen] - slope * dx[seen]
    a = float(np.median(level))
    return a, np.abs(level - a) - 2.0 * std[seen], float(seen.mean())


Grid = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]


def _level_grid(
    emap: ElevationMap, x: float, y: float, half: tuple[float, float], rules: PatchRules, slope: float
) -> Grid | None:
    """Eq. (1) whole at every lattice centre within ``rules.reach`` of ``(x, y)``: ``ok`` (A, B) bool, and
    the centres' x, y and heights ``a`` (A, B) m; None when the window leaves the map. An unseen cell
    fails eq. (1) (its standard deviation is inf)."""
    r = emap.settings.resolution
    ci = emap.cells(np.array([x, y])) - emap.corner  # the planned centre's cell
    reach = np.floor(np.array(rules.reach) / r).astype(np.int64)
    win = np.floor(np.array(half) / r + 0.5).astype(np.int64)  # cells either side that ``half`` overlaps
    lo, hi = ci - reach - win, ci + reach + win + 1
    if np.any(lo < 0) or np.any(hi > emap.n):
        return None
    shape = (2 * int(win[0]) + 1, 2 * int(win[1]) + 1)
    u = np.repeat(np.arange(-win[0], win[0] + 1) * r, shape[1])  # each window cell's x from its centre
    h = sliding_window_view(emap.height[lo[0] : hi[0], lo[1] : hi[1]], shape)  # (A, B, wx, wy)
    std = sliding_window_view(np.sqrt(emap.variance[lo[0] : hi[0], lo[1] : hi[1]]), shape)
    level = h.reshape(*h.shape[:2], -1) - slope * u
    std = std.reshape(*std.shape[:2], -1)
    a = np.median(level, axis=-1)
    dev = np.abs(level - a[..., None]) - 2.0 * std
    ok = (np.nan_to_num(dev, nan=np.inf).max(axis=-1) <= rules.flat_tol) & (std.max(axis=-1) <= rules.max_std)
    di, dj = np.meshgrid(np.arange(-reach[0], reach[0] + 1), np.arange(-reach[1], reach[1] + 1), indexing="ij")
    return ok, (emap.corner[0] + ci[0] + di + 0.5) * r, (emap.corner[1] + ci[1] + dj + 0.5) * r, a


def _centre(ok: np.ndarray) -> tuple[int, int]:
    """The index of the planned centre's own cell in a :func:`_level_grid` window."""
    return ok.shape[0] // 2, ok.shape[1] // 2


def _room(ok: np.ndarray, cx: np.ndarray, cy: np.ndarray, k: tuple[int, int]) -> tuple[float, float, float, float]:
    """The run of centres where eq. (1) holds through index ``k`` along x and along y, as (x_lo, x_hi, y_lo,
    y_hi) m (the centre itself when it does not hold there). It never reaches past the window judged:
    beyond ``reach`` nothing was judged."""
    a, b = k
    if not ok[a, b]:
        return float(cx[a, b]), float(cx[a, b]), float(cy[a, b]), float(cy[a, b])
    a0, a1, b0, b1 = a, a, b, b
    while a0 > 0 and ok[a0 - 1, b]:
        a0 -= 1
    while a1 < ok.shape[0] - 1 and ok[a1 + 1, b]:
        a1 += 1
    while b0 > 0 and ok[a, b0 - 1]:
        b0 -= 1
    while b1 < ok.shape[1] - 1 and ok[a, b1 + 1]:
        b1 += 1
    return float(cx[a0, b]), float(cx[a1, b]), float(cy[a, b0]), float(cy[a, b1])
