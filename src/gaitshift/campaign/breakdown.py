"""Where a campaign's robot falls and why: survival per axis, the worst cell of every pair of axes,
and the falls counted by cause (the report's tables, :mod:`gaitshift.campaign.report`).

Survival of a level = cases that did not fall / cases run without an error at that level of the axis
(every other axis pooled); numbers drawn at random are binned (:func:`gaitshift.campaign.figures.levels`).
A pair's worst cell is the (x, y) level pair of lowest survival among the cells with at least
:data:`MIN_CELL` cases. Causes: the ``fall_cause`` column (:mod:`gaitshift.sim.fall_cause`). The
perception table (:func:`perception_markdown`) gives, per scenario and terrain (what the planner was
told), the survival and the elevation map's numbers of the rows that have them.
"""

from __future__ import annotations

import itertools
import statistics
from collections import Counter
from pathlib import Path
from typing import Any

from gaitshift.campaign.axes import AXES
from gaitshift.campaign.figures import levels, survival_grid

__all__ = [
    "MIN_CELL",
    "axis_survival",
    "breakdown_markdown",
    "cause_counts",
    "perception_markdown",
    "swept_axes",
    "worst_cells",
]

#: the fewest cases a cell needs to be the worst of its pair
MIN_CELL = 10


def _ran(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    return [r for r in rows if r["error"] is None and r["fell"] is not None]


#: axes that are not conditions of the robot (a run's random draws): left out of the tables
NOT_CONDITIONS = ("seed",)


def swept_axes(rows: list[dict[str, Any]]) -> list[str]:
    """The axes (registry order, but :data:`NOT_CONDITIONS`) that take two values or more over ``rows``."""
    return [a for a in AXES if a not in NOT_CONDITIONS and len({r[a] for r in rows if r[a] is not None}) > 1]


def axis_survival(rows: list[dict[str, Any]], axis: str) -> list[tuple[Any, int, float]]:
    """Per level of ``axis``: (level, cases, survival fraction) over the cases run without an error."""
    ok = _ran(rows)
    names, index = levels(ok, axis)
    out = []
    for i, name in enumerate(names):
        mine = [r for r, k in zip(ok, index, strict=True) if k == i]
        if mine:
            out.append((name, len(mine), sum(not r["fell"] for r in mine) / len(mine)))
    return out


def worst_cells(rows: list[dict[str, Any]]) -> list[tuple[str, str, Any, Any, int, float]]:
    """Per pair of swept axes: (x, y, x level, y level, cases, survival) of its worst cell with at
    least :data:`MIN_CELL` cases, lowest survival first."""
    out = []
    for x, y in itertools.combinations(swept_axes(rows), 2):
        g = survival_grid(rows, x, y)
        if g is None:
            continue
        cells = [(g.rate[i, j], i, j) for i in range(len(g.ys)) for j in range(len(g.xs)) if g.n[i, j] >= MIN_CELL]
        if cells:
            rate, i, j = min(cells)
            out.append((x, y, g.xs[j], g.ys[i], int(g.n[i, j]), float(rate)))
    return sorted(out, key=lambda c: c[-1])


def cause_counts(rows: list[dict[str, Any]]) -> Counter[str]:
    """Falls per cause ("unclassified" for a fall without one)."""
    return Counter(str(r.get("fall_cause") or "unclassified") for r in _ran(rows) if r["fell"])


def _fmt_level(v: Any) -> str:
    return f"{v:g}" if isinstance(v, int | float) and not isinstance(v, bool) else str(v)


def breakdown_markdown(rows: list[dict[str, Any]], pairs: int = 12) -> list[str]:
    """The tables in Markdown: causes, survival per axis, the ``pairs`` worst pair cells, and the
    perception table when rows have one (:func:`perception_markdown`)."""
    md = ["", "## Falls by cause", "", "| cause | falls | share of falls |", "|---|---|---|"]
    causes = cause_counts(rows)
    total = sum(causes.values())
    md += [f"| {c} | {n} | {100 * n / total:.0f} % |" for c, n in causes.most_common()] or ["| - | 0 | - |"]
    md += ["", "## Survival per axis (other axes pooled)", ""]
    for axis in swept_axes(rows):
        cells = axis_survival(rows, axis)
        md.append(f"- `{axis}`: " + ", ".join(f"{_fmt_level(v)}: {100 * s:.0f} % ({n})" for v, n, s in cells))
    md += ["", f"## The worst cell of each pair of axes (cells of >= {MIN_CELL} cases; worst {pairs})", ""]
    md += ["| x | y | x level | y level | cases | survival |", "|---|---|---|---|---|---|"]
    for x, y, xv, yv, n, s in worst_cells(rows)[:pairs]:
        md.append(f"| {x} | {y} | {_fmt_level(xv)} | {_fmt_level(yv)} | {n} | {100 * s:.0f} % |")
    return md + perception_markdown(rows)


def _stat(rows: list[dict[str, Any]], key: str, scale: float = 1.0, digits: int = 1, reduce: Any = None) -> str:
    """``scale`` times the median (or ``reduce``) of the column ``key`` over the rows that have it; "-": none."""
    vals = [r[key] for r in rows if r[key] is not None]
    return "-" if not vals else f"{scale * (reduce or statistics.median)(vals):.{digits}f}"


def perception_markdown(rows: list[dict[str, Any]]) -> list[str]:
    """Per scenario and ``terrain`` (the scenario's own when not swept) over the cases run without an
    error: cases, survival, the median pelvis end x (m), the medians over the cases of the map error's
    median and p95 under the standing soles (mm), the least and the median edge distance (mm) and the
    median re-plans; no lines when no row has a map error."""
    ok = [r for r in _ran(rows) if r.get("map_error_median") is not None]
    if not ok:
        return []
    md = ["", "## Perception (per scenario and what the planner was told of the terrain)", ""]
    md += ["| scenario | terrain | cases | survival | pelvis end x, m | map error median / p95, mm |"]
    md[-1] += " edge distance least / median, mm | re-plans |"
    md.append("|---|---|---|---|---|---|---|---|")
    groups: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for r in ok:
        groups.setdefault((Path(str(r["scenario"])).stem, str(r["terrain"] or "scenario's")), []).append(r)
    for (sc, terrain), mine in sorted(groups.items()):
        alive = sum(not r["fell"] for r in mine)
        md.append(
            f"| {sc} | {terrain} | {len(mine)} | {alive} of {len(mine)} | {_stat(mine, 'end_x')} | "
            f"{_stat(mine, 'map_error_median', 1e3)} / {_stat(mine, 'map_error_p95', 1e3)} | "
            f"{_stat(mine, 'edge_distance_min', 1e3, reduce=min)} / {_stat(mine, 'edge_distance_median', 1e3)} | "
            f"{_stat(mine, 'replans', digits=0)} |"
        )
    return md
