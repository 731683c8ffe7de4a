"""Figures of a campaign: survival heatmaps over two axes and the fall-time histogram (PNG).

Survival of a cell = cases that did not fall / cases run without an error, over every case whose two
axis values are the cell's (the other axes pooled). An axis of more than :data:`MAX_LEVELS` distinct
numbers (a sample spec's draws) is cut into :data:`BINS` bins of equal width, each named by its
centre (:func:`levels`). Rows are plain dicts of the store's table.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.plots.files import save_figure

__all__ = ["BINS", "MAX_LEVELS", "SurvivalGrid", "fall_time_histogram", "levels", "survival_grid", "survival_heatmap"]

#: an axis with more distinct numbers than this is binned; into this many bins
MAX_LEVELS, BINS = 8, 5

#: axis -> its label on a figure
LABELS = {
    "speed": "commanded speed (m/s)",
    "push_impulse": "push impulse (N s)",
    "push_velocity": "push (m/s of base velocity)",
    "mass_scale": "mass scale (plant / model)",
    "friction": "floor friction coefficient",
    "latency": "latency (ticks)",
    "noise_scale": "sensor noise scale",
    "yaw_rate": "yaw rate (rad/s)",
}


class SurvivalGrid:
    """Survival fraction ``rate[i, j]`` (nan where no case) and case count ``n[i, j]`` for
    ``ys[i]`` x ``xs[j]``."""

    def __init__(self, x: str, y: str, xs: list[Any], ys: list[Any], rate: np.ndarray, n: np.ndarray) -> None:
        self.x, self.y, self.xs, self.ys, self.rate, self.n = x, y, xs, ys, rate, n


def _ran(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    return [r for r in rows if r["error"] is None and r["fell"] is not None]


def levels(rows: list[dict[str, Any]], axis: str) -> tuple[list[Any], list[int | None]]:
    """The levels of ``axis`` over ``rows`` and each row's level index (None: no value): its distinct
    values, or :data:`BINS` equal-width bins (named by their centres, 3 significant digits) when it
    has more than :data:`MAX_LEVELS` distinct numbers."""
    vals = [r[axis] for r in rows]
    distinct = sorted({v for v in vals if v is not None})
    numeric = all(isinstance(v, int | float) and not isinstance(v, bool) for v in distinct)
    if len(distinct) <= MAX_LEVELS or not numeric:
        return distinct, [None if v is None else distinct.index(v) for v in vals]
    lo, hi = float(distinct[0]), float(distinct[-1])
    width = (hi - lo) / BINS
    names = [float(f"{lo + (i + 0.5) * width:.3g}") for i in range(BINS)]
    return names, [None if v is None else min(BINS - 1, int((v - lo) / width)) for v in vals]


def survival_grid(rows: list[dict[str, Any]], x: str, y: str) -> SurvivalGrid | None:
    """The survival over axes ``x`` and ``y`` (:func:`levels`), or None unless both take two values
    or more."""
    ok = _ran(rows)
    xs, jx = levels(ok, x)
    ys, iy = levels(ok, y)
    if len(xs) < 2 or len(ys) < 2:
        return None
    alive = np.zeros((len(ys), len(xs)))
    n = np.zeros((len(ys), len(xs)), dtype=int)
    for r, i, j in zip(ok, iy, jx, strict=True):
        if i is None or j is None:
            continue
        n[i, j] += 1
        alive[i, j] += not r["fell"]
    rate = np.divide(alive, n, out=np.full(alive.shape, np.nan), where=n > 0)
    return SurvivalGrid(x, y, xs, ys, rate, n)


def survival_heatmap(grid: SurvivalGrid, path: Path, title: str) -> Path:
    """Draw ``grid`` as a heatmap with the percentage in each cell; write ``path`` (PNG) atomically."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(1.1 * len(grid.xs) + 2.5, 0.7 * len(grid.ys) + 1.8))
    im = ax.imshow(grid.rate * 100, origin="lower", cmap="RdYlGn", vmin=0, vmax=100, aspect="auto")
    ax.set_xticks(range(len(grid.xs)), [f"{v:g}" for v in grid.xs])
    ax.set_yticks(range(len(grid.ys)), [f"{v:g}" for v in grid.ys])
    ax.set_xlabel(LABELS.get(grid.x, grid.x))
    ax.set_ylabel(LABELS.get(grid.y, grid.y))
    for i in range(len(grid.ys)):
        for j in range(len(grid.xs)):
            if grid.n[i, j]:
                ax.text(j, i, f"{100 * grid.rate[i, j]:.0f}", ha="center", va="center", fontsize=8)
    fig.colorbar(im, ax=ax, label="survival (%)")
    ax.set_title(title, fontsize=9)
    return save_figure(fig, path, dpi=110)


def fall_time_histogram(rows: list[dict[str, Any]], path: Path, title: str) -> Path | None:
    """Histogram of the fall times (s of plan time) of the cases that fell; None when none fell."""
    t = np.array([r["t_fall"] for r in _ran(rows) if r["fell"] and r["t_fall"] is not None])
    if len(t) == 0:
        return None
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.5, 3.2))
    ax.hist(t, bins=min(30, max(5, len(t) // 5)), color="tab:red", alpha=0.8)
    ax.set_xlabel("fall time (s of plan time)")
    ax.set_ylabel("cases")
    ax.set_title(title, fontsize=9)
    return save_figure(fig, path, dpi=110)
