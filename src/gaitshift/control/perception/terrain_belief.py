"""The terrain the controller believes in: the elevation map's profile along the path, as pieces.

The planner's ground is a height profile z(x) made of flat treads and ramps
(:class:`~gaitshift.models.terrain.Terrain`). The belief is read off the controller's map
(:mod:`gaitshift.control.perception.elevation_map`) along the band of rows the feet walk on
(``y_lo <= y <= y_hi``):

1. **Columns.** A cell counts when its height's standard deviation is at most ``max_std`` m (far cells,
   seen once at the camera's range, are too noisy to plan on). Each column of cells (one x) is *seen*
   when at least ``min_seen`` of its band cells count; its height is their median (robust to a stray
   cell on a riser's face).
2. **Pieces.** Seen columns are cut where neighbours differ by more than ``jump`` m or a column is not
   seen. Runs that meet across unseen columns at heights within ``jump`` are one (the camera missed a
   patch: far away its rows of rays fall a few cells apart); then runs shorter than ``min_columns`` are
   dropped (a cell across a riser mixes two treads). Each run is fitted by least squares,
   :math:`z = a + b x`, and split where two lines fit it best while a residual exceeds ``fit_tol`` m
   (the foot of a ramp: the slope changes, the height does not jump). A piece with :math:`|b| <`
   ``flat_slope``, or shorter than ``min_ramp`` m, is a flat tread at its mean height (a ramp shorter
   than a stride is a riser seen from afar); neighbour treads within ``jump / 2`` are one (noise makes
   no step).
3. **Breaks.** Where two pieces of one run meet, the ground is continuous: the break is where their
   lines cross (a ramp's foot), when that is within a cell. Across a gap the break lies at the end of
   the higher piece: the edge of a step is where its top ends. Going up, the riser faces the camera
   and its cells (heights between the two treads) are dropped, so the gap lies before the upper
   tread's first cell; going down, the upper tread hides the foot of its riser, so the gap lies after
   its last cell. The gap itself is kept (:attr:`Belief.gaps`): an edge lies somewhere in it. Flat
   ground at the first and last runs' end heights reaches :data:`REACH` m beyond them, so the belief
   covers the whole path.

Footholds the feet stood on (``stood``: x from, x to, height) fill columns the camera never saw
(under the feet at the start: the camera looks 0.36 m ahead). Nothing here reads the world.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from gaitshift.control.perception.elevation_map import ElevationMap
from gaitshift.models.terrain import Piece, Terrain

__all__ = ["REACH", "Belief", "BeliefSettings", "profile", "terrain_belief"]

#: how far, m, the first and last pieces of a belief reach beyond what was seen
REACH = 1000.0


@dataclass(frozen=True)
class BeliefSettings:
    """How the map's profile becomes pieces (module docstring): ``max_std`` (m, of a cell that counts),
    ``min_seen`` (share of a column's band
    cells), ``jump`` (m between neighbour columns), ``min_columns`` (cells of a piece), ``fit_tol`` (m, a
    piece's largest residual), ``min_ramp`` (m, the shortest ramp), ``flat_slope`` (dz/dx below which a
    piece is flat)."""

    max_std: float = 0.03
    min_seen: float = 0.2
    jump: float = 0.02
    min_columns: int = 3
    fit_tol: float = 0.02
    min_ramp: float = 0.3
    flat_slope: float = 0.03


@dataclass(frozen=True)
class Belief:
    """The believed ``terrain``, the x range ``seen`` (m, from, to) of the ground it was read from (seen
    or stood on; beyond it the terrain is extrapolated flat) and the ``gaps`` (m, from, to) between two
    pieces of different heights where no cell was seen or kept (a riser, the shadow of a step down, the
    camera's blind band): somewhere in each lies an edge, so no sole stands there."""

    terrain: Terrain
    seen: tuple[float, float]
    gaps: tuple[tuple[float, float], ...] = ()


def profile(
    emap: ElevationMap,
    y_lo: float,
    y_hi: float,
    settings: BeliefSettings,
    stood: Sequence[tuple[float, float, float]] = (),
) -> tuple[np.ndarray, np.ndarray]:
    """Column centres x (n,) m and heights (n,) m of the map's band ``[y_lo, y_hi]`` m (NaN: not seen;
    module docstring, step 1), unseen columns filled from ``stood`` soles (x from, x to, height m)."""
    r = emap.settings.resolution
    x = (emap.corner[0] + np.arange(emap.n) + 0.5) * r
    y = (emap.corner[1] + np.arange(emap.n) + 0.5) * r
    rows = (y >= y_lo) & (y <= y_hi)
    h = emap.height[:, rows]
    seen = emap.variance[:, rows] <= settings.max_std**2
    count = seen.sum(axis=1)
    ok = count >= max(1, int(np.ceil(settings.min_seen * max(int(rows.sum()), 1))))
    z = np.full(emap.n, np.nan)
    if ok.any():
        # the median of the seen cells: unseen ones sorted to the end as +inf
        srt = np.sort(np.where(seen[ok], h[ok], np.inf), axis=1)
        c = count[ok]
        lo, hi = srt[np.arange(len(c)), (c - 1) // 2], srt[np.arange(len(c)), c // 2]
        z[ok] = 0.5 * (lo + hi)
    for x0, x1, zs in stood:
        fill = np.isnan(z) & (x >= x0) & (x <= x1)
        z[fill] = zs
    return x, z


def terrain_belief(
    emap: ElevationMap,
    y_lo: float,
    y_hi: float,
    settings: BeliefSettings | None = None,
    stood: Sequence[tuple[float, float, float]] = (),
) -> Belief | None:
    """The believed terrain of the band ``[y_lo, y_hi]`` m (module docstring), or None when nothing is
    seen or stood on."""
    s = settings or BeliefSettings()
    x, z = profile(emap, y_lo, y_hi, s, stood)
    r = emap.settings.resolution
    seen = ~np.isnan(z)
    cut = np.r_[True, ~seen[1:] | ~seen[:-1] | (np.abs(np.diff(np.where(seen, z, 0.0))) > s.jump)]
    run = np.cumsum(cut)
    runs = [np.flatnonzero((run == k) & seen) for k in np.unique(run[seen])]
    runs = [i for i in _merged(runs, z, s.jump) if len(i) >= s.min_columns]
    runs = [j for i in runs for j in _split(x, z, i, s.fit_tol, s.min_columns)]
    if not runs:
        return None
    fits = [_fit(x[i], z[i], s.flat_slope, s.min_ramp - r) for i in runs]
    runs, fits = _joined(runs, fits, z, s.jump / 2)
    ends = [(x[i[0]] - r / 2, x[i[-1]] + r / 2) for i in runs]
    rows = [[e[0], e[1], a + b * e[0], a + b * e[1]] for (a, b), e in zip(fits, ends, strict=True)]
    gaps = tuple((ends[k - 1][1], ends[k][0]) for k in range(1, len(ends)) if ends[k][0] - ends[k - 1][1] > r / 2)
    for k in range(1, len(rows)):
        _meet(rows[k - 1], rows[k], fits[k - 1], fits[k], r)
    first, last = rows[0], rows[-1]
    pieces = [Piece(-REACH, first[0], first[2], first[2])]
    pieces += [Piece(*row) for row in rows]
    pieces.append(Piece(last[1], REACH, last[3], last[3]))
    return Belief(Terrain(tuple(pieces)), (float(ends[0][0]), float(ends[-1][1])), gaps)


def _meet(left: list[float], right: list[float], fl: tuple[float, float], fr: tuple[float, float], r: float) -> None:
    """Set the break between two neighbour pieces (rows x0, x1, z0, z1, changed in place; their lines
    ``z = a + b x`` are ``fl`` and ``fr``): across a gap (unseen or dropped cells), at the end of the
    higher one (module docstring, step 3); where they touch (a run split at a change of slope), where
    the two lines cross when that is within a cell of where they touch (a ramp's foot: the ground is
    continuous), else a step where they touch."""
    if right[0] - left[1] > r / 2:  # a gap
        x = left[1] if left[3] > right[2] else right[0]
        left[1], right[0] = x, x
        return
    right[0] = left[1]  # they touch: one x (the cell edge, up to rounding)
    if fl[1] == fr[1]:
        return  # two parallel pieces (flat ones at different heights): a step where they touch
    x = (fr[0] - fl[0]) / (fl[1] - fr[1])
    if abs(x - left[1]) <= r:
        h = fl[0] + fl[1] * x
        left[1], right[0], left[3], right[2] = x, x, h, h


def _joined(
    runs: list[np.ndarray], fits: list[tuple[float, float]], z: np.ndarray, tol: float
) -> tuple[list[np.ndarray], list[tuple[float, float]]]:
    """Neighbour flat pieces within ``tol`` m of each other joined into one at their mean height (noise
    makes no step)."""
    out_r: list[np.ndarray] = []
    out_f: list[tuple[float, float]] = []
    for i, f in zip(runs, fits, strict=True):
        if out_f and out_f[-1][1] == 0.0 and f[1] == 0.0 and abs(out_f[-1][0] - f[0]) <= tol:
            out_r[-1] = np.r_[out_r[-1], i]
            out_f[-1] = (float(z[out_r[-1]].mean()), 0.0)
        else:
            out_r.append(i)
            out_f.append(f)
    return out_r, out_f


def _fit(x: np.ndarray, z: np.ndarray, flat_slope: float, min_span: float) -> tuple[float, float]:
    """Least-squares line ``z = a + b x`` of a run; flat (``b = 0``, ``a`` the mean) when ``|b| <
    flat_slope`` or its columns span less than ``min_span`` m."""
    if len(x) < 2 or np.ptp(x) < min_span:
        return float(z.mean()), 0.0
    b, a = np.polyfit(x, z, 1)
    if abs(b) < flat_slope:
        return float(z.mean()), 0.0
    return float(a), float(b)


def _split(x: np.ndarray, z: np.ndarray, i: np.ndarray, tol: float, least: int) -> list[np.ndarray]:
    """The run of columns ``i`` cut where two lines fit it best (the least total squared residual) until
    every part's line fits within ``tol`` m (parts of at least ``least`` columns)."""
    n = len(i)
    if n < 2 * least:
        return [i]
    b, a = np.polyfit(x[i], z[i], 1)
    if np.abs(z[i] - (a + b * x[i])).max() <= tol:
        return [i]
    w = least + int(
        np.argmin([_sse(x[i[:m]], z[i[:m]]) + _sse(x[i[m:]], z[i[m:]]) for m in range(least, n - least + 1)])
    )
    return _split(x, z, i[:w], tol, least) + _split(x, z, i[w:], tol, least)


def _sse(x: np.ndarray, z: np.ndarray) -> float:
    """Squared residual of the least-squares line through the points (x, z)."""
    xc, zc = x - x.mean(), z - z.mean()
    sxx = float(xc @ xc)
    return float(zc @ zc) - (float(xc @ zc) ** 2 / sxx if sxx > 0 else 0.0)


def _merged(runs: list[np.ndarray], z: np.ndarray, jump: float) -> list[np.ndarray]:
    """Neighbour runs of columns joined when the ground goes on across the gap between them: the last
    columns of one and the first of the next within ``jump`` m (means of two columns each)."""
    out: list[np.ndarray] = []
    for i in runs:
        if out and abs(float(z[out[-1][-2:]].mean()) - float(z[i[:2]].mean())) <= jump:
            out[-1] = np.r_[out[-1], i]
        else:
            out.append(i)
    return out
