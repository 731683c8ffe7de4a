"""The report of ``gaitshift robot tune`` (markdown): the start and why, every candidate's runs, the pick."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from gaitshift.tuning.search import FLIGHT_REACHED, TuneResult, flight_short

__all__ = ["report"]


def _cell(rows: list[dict[str, Any]]) -> str:
    """One candidate on one scenario over its seeds: falls, the worst contact accuracy and the least share of
    its planned flight achieved (where it plans one)."""
    falls = [
        f"{r['seed']}@{r['t_fall']:.2f}s" if r.get("t_fall") is not None else str(r["seed"]) for r in rows if r["fell"]
    ]
    errors = [r for r in rows if r.get("error")]
    acc = [r["contact_accuracy"] for r in rows if r.get("contact_accuracy") is not None]
    text = "no fall" if not falls else "fell " + " ".join(falls)
    if errors:
        text += f", {len(errors)} error(s)"
    flight = [r["flight_ratio"] for r in rows if r.get("flight_ratio") is not None]
    text += f", contact >= {100 * min(acc):.1f} %" if acc else ""
    return text + (f", flight >= {min(flight):.2f} of planned" if flight else "")


def report(result: TuneResult, robot: str) -> str:
    """Markdown of ``result`` for the robot YAML ``robot``."""
    s = result.start
    lines = [
        f"# gaitshift robot tune {robot}",
        "",
        "Start (from the model, gaitshift/tuning/start.py):",
        f"- knee capacity n = {s.knee_ratio:.2f} (knee torque limit / knee torque holding the weight on one sole):"
        f" flight scale {s.flight_scale:.3f} (eq. 1)",
        f"- yaw joints {s.yaw_joints[0]}, {s.yaw_joints[1]}: turn rate cap "
        + (f"{s.max_yaw_rate:.3f} rad/s (eq. 2)" if s.max_yaw_rate is not None else "none (no speed limit known)"),
        "",
    ]
    by: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for r in result.rows:
        path = Path(r["scenario"])
        by.setdefault((path.parent.name, path.stem), []).append(r)
    scenarios = sorted({k[1] for k in by})
    lines += ["| candidate | " + " | ".join(scenarios) + " |", "|---" * (len(scenarios) + 1) + "|"]
    for c in result.grid:
        cells = [_cell(by.get((c.name, sc), [])) for sc in scenarios]
        mark = " **(picked)**" if c == result.best else ""
        lines.append(f"| {c.name}{mark} | " + " | ".join(cells) + " |")
    wall = sum(r.get("wall_time") or 0.0 for r in result.rows)
    lines += ["", f"Picked: `gait: {result.best.keys()}`. {len(result.rows)} runs, {wall:.0f} s of simulation."]
    flown = [r for r in result.rows if r.get("flight_ratio") is not None]
    if flown and all(flight_short(r) > 0 for r in flown):
        lines.append(
            f"No candidate's running achieved {FLIGHT_REACHED:.0%} of its planned flight: the flight is bound by"
            " the robot, not by the grid (the pick comes closest among the fewest falls)."
        )
    return "\n".join(lines) + "\n"
