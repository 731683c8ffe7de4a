"""``gaitshift campaign report DIR``: the survival maps, fall times and per-robot table of a campaign.

Writes into ``DIR/report/``: ``survival_speed_push.png`` (speed x push impulse),
``survival_speed_push_velocity.png`` (speed x push as a velocity), ``survival_mass_friction.png``
(mass scale x friction), ``fall_times.png`` and ``summary.md`` (the same maps as Markdown tables, the
falls by cause, survival per axis, the worst cell of each pair of axes and, when the rows have an
elevation map's numbers, survival and map error per scenario and terrain
(:mod:`gaitshift.campaign.breakdown`), the per-robot table and the run's totals). A map
is drawn only when both its axes take two values or more. Cases per hour per core = 3600 / the mean
``wall_time`` of one case in its worker (each worker runs one case at a time on one core).
"""

from __future__ import annotations

import statistics
from pathlib import Path
from typing import Any

import yaml

from gaitshift.campaign.breakdown import breakdown_markdown
from gaitshift.campaign.figures import SurvivalGrid, fall_time_histogram, survival_grid, survival_heatmap
from gaitshift.campaign.store import Store
from gaitshift.common.atomic import atomic_path
from gaitshift.errors import InputError

__all__ = ["MAPS", "robot_table", "write_report"]

#: the survival maps: (x axis, y axis, file stem)
MAPS = (
    ("speed", "push_impulse", "survival_speed_push"),
    ("speed", "push_velocity", "survival_speed_push_velocity"),
    ("friction", "mass_scale", "survival_mass_friction"),
)


def _fmt(x: Any, spec: str = ".3f") -> str:
    return "-" if x is None else format(x, spec)


def _mean(xs: list[Any]) -> float | None:
    vals = [x for x in xs if x is not None]
    return statistics.fmean(vals) if vals else None


def robot_table(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per robot (the ``robot`` axis; "scenario's" when not swept): cases, errors, survival %, median
    fall time, mean speed and heading errors, worst torque and joint-speed fractions."""
    out = []
    for robot in sorted({str(r["robot"] or "scenario's") for r in rows}):
        mine = [r for r in rows if str(r["robot"] or "scenario's") == robot]
        ran = [r for r in mine if r["error"] is None and r["fell"] is not None]
        falls = [r["t_fall"] for r in ran if r["fell"] and r["t_fall"] is not None]
        out.append(
            {
                "robot": robot,
                "cases": len(mine),
                "errors": len(mine) - len(ran),
                "survival_pct": 100.0 * sum(not r["fell"] for r in ran) / len(ran) if ran else None,
                "median_t_fall": statistics.median(falls) if falls else None,
                "speed_error": _mean([r["speed_error"] for r in ran]),
                "heading_error": _mean([r["heading_error"] for r in ran]),
                "peak_torque_fraction": max((r["peak_torque_fraction"] or 0.0 for r in ran), default=None),
                "joint_speed_fraction": max((r["joint_speed_fraction"] or 0.0 for r in ran), default=None),
            }
        )
    return out


def _grid_markdown(g: SurvivalGrid) -> list[str]:
    head = f"| {g.y} \\ {g.x} | " + " | ".join(f"{v:g}" for v in g.xs) + " |"
    lines = [head, "|" + "---|" * (len(g.xs) + 1)]
    for i in reversed(range(len(g.ys))):
        cells = [f"{100 * g.rate[i, j]:.0f}% ({g.n[i, j]})" if g.n[i, j] else "-" for j in range(len(g.xs))]
        lines.append(f"| {g.ys[i]:g} | " + " | ".join(cells) + " |")
    return lines


def _spec_of(path: Path) -> dict[str, Any]:
    """The campaign's spec (its name and task for the report) or {} without one; a spec that is not a
    YAML mapping is one :class:`InputError`."""
    if not path.exists():
        return {}
    try:
        spec = yaml.safe_load(path.read_text())
    except (yaml.YAMLError, UnicodeDecodeError, OSError) as exc:
        raise InputError("spec.yaml", str(path), f"a campaign spec in YAML ({str(exc).splitlines()[0][:80]})") from None
    if not isinstance(spec, dict):
        raise InputError("spec.yaml", str(path), "a campaign spec (a YAML mapping)")
    return spec


def _totals(store: Store, rows: list[dict[str, Any]]) -> list[str]:
    spec = _spec_of(store.root / "spec.yaml")
    walls = [r["wall_time"] for r in rows if r["wall_time"] is not None]
    ran = [r for r in rows if r["error"] is None and r["fell"] is not None]
    lines = [
        f"# Campaign {spec.get('name', store.root.name)}",
        "",
        f"- task: {spec.get('task', '?')}; rows: {len(rows)}; dataset complete: {store.complete_marker.exists()}",
        f"- cases with an error (no metrics): {len(rows) - len(ran)}",
    ]
    if ran:
        lines.append(f"- survival over all cases run: {100 * sum(not r['fell'] for r in ran) / len(ran):.1f} %")
    if walls:
        mean = statistics.fmean(walls)
        lines.append(
            f"- wall time per case in its worker: mean {mean:.2f} s, median {statistics.median(walls):.2f} s, "
            f"sum {sum(walls) / 3600:.2f} core-hours; {3600 / mean:.0f} cases per hour per core"
        )
    cpus = [r["cpu_time"] for r in rows if r["cpu_time"] is not None]
    if cpus:
        lines.append(f"- CPU time per case: mean {statistics.fmean(cpus):.2f} s ({len(cpus)} cases recorded it)")
    versions = sorted({str(r["gaitshift_version"]) for r in rows})
    lines.append(f"- gaitshift version(s): {', '.join(versions)}")
    return lines


def write_report(folder: str | Path) -> list[Path]:
    """Write the report of the campaign in ``folder`` (module docstring); return the files written."""
    store = Store(folder)
    out = store.root / "report"
    if out.exists() and not out.is_dir():
        raise InputError("DIR", str(store.root), f"a campaign folder whose report/ is a folder ({out} is a file)")
    rows = store.table().to_pylist()
    written: list[Path] = []
    md = _totals(store, rows)
    for x, y, stem in MAPS:
        g = survival_grid(rows, x, y)
        if g is None:
            continue
        title = f"survival (%) over {y} x {x}\n(other axes pooled; cases per cell in summary.md)"
        written.append(survival_heatmap(g, out / f"{stem}.png", title))
        md += ["", f"## Survival: {y} x {x}", "", f"![{stem}]({stem}.png)", "", *_grid_markdown(g)]
    hist = fall_time_histogram(rows, out / "fall_times.png", "fall times of the cases that fell")
    if hist is not None:
        written.append(hist)
        md += ["", "## Fall times", "", "![fall_times](fall_times.png)"]
    md += breakdown_markdown(rows)
    md += ["", "## Per robot", "", "| robot | cases | errors | survival % | median t_fall s | speed err m/s |"]
    md[-1] += " heading err rad | peak torque frac | joint speed frac |"
    md.append("|---|---|---|---|---|---|---|---|---|")
    for t in robot_table(rows):
        md.append(
            f"| {t['robot']} | {t['cases']} | {t['errors']} | {_fmt(t['survival_pct'], '.1f')} | "
            f"{_fmt(t['median_t_fall'], '.2f')} | {_fmt(t['speed_error'])} | {_fmt(t['heading_error'])} | "
            f"{_fmt(t['peak_torque_fraction'], '.2f')} | {_fmt(t['joint_speed_fraction'], '.2f')} |"
        )
    with atomic_path(out / "summary.md") as tmp:
        tmp.write_text("\n".join(md) + "\n")
    return [*written, out / "summary.md"]
