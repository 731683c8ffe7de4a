"""Figures of a campaign: survival heatmaps over two axes and the fall-time histogram (PNG).

Survival of a cell = cases that did not fall / cases run without an error, over every case whose two
axis values are the cell's (the other axes pooled). Rows are plain dicts of the store's table.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.plots.files import save_figure

__all__ = ["SurvivalGrid", "fall_time_histogram", "survival_grid", "survival_heatmap"]

#: axis -> its label on a figure
LABELS = {
    "speed": "commanded speed (m/s)",
    "push_impulse": "push impulse (N s)",
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


def survival_grid(rows: list[dict[str, Any]], x: str, y: str) -> SurvivalGrid | None:
    """The survival over axes ``x`` and ``y``, or None unless both take two values or more."""
    ok = _ran(rows)
    xs = sorted({r[x] for r in ok if r[x] is not None})
    ys = sorted({r[y] for r in ok if r[y] is not None})
    if len(xs) < 2 or len(ys) < 2:
        return None
    alive = np.zeros((len(ys), len(xs)))
    n = np.zeros((len(ys), len(xs)), dtype=int)
    for r in ok:
        if r[x] is None or r[y] is None:
            continue
        i, j = ys.index(r[y]), xs.index(r[x])
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
