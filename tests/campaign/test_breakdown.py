"""The report's breakdown counts what the rows say: drawn numbers fall into equal-width bins named by
their centres, survival per bin and per pair cell follows the rule that made the rows, and the falls
are counted by cause."""

from __future__ import annotations

import numpy as np

from gaitshift.campaign.breakdown import axis_survival, breakdown_markdown, cause_counts, worst_cells
from gaitshift.campaign.figures import BINS, levels
from gaitshift.campaign.store import SCHEMA


def _rows(n=400) -> list[dict]:
    """Random speeds in [0, 2] and frictions in [0.3, 1.2]; a case falls when speed > 1.6 or friction
    < 0.39, by slip when the friction made it fall, else by reach."""
    rng = np.random.default_rng(0)
    rows = []
    for i, (v, mu) in enumerate(zip(rng.uniform(0, 2, n), rng.uniform(0.3, 1.2, n), strict=True)):
        fell = bool(v > 1.6 or mu < 0.39)
        cause = ("slip" if mu < 0.39 else "reach") if fell else None
        row = dict.fromkeys(SCHEMA.names) | {"task": "simulate", "speed": float(v), "friction": float(mu)}
        rows.append(row | {"fell": fell, "fall_cause": cause, "case_hash": str(i), "noise": "typical"})
    return rows


def test_drawn_numbers_fall_into_equal_width_bins_named_by_their_centres():
    rows = _rows()
    names, index = levels(rows, "speed")
    lo, hi = min(r["speed"] for r in rows), max(r["speed"] for r in rows)
    w = (hi - lo) / BINS
    assert len(names) == BINS and np.allclose(names, [lo + (i + 0.5) * w for i in range(BINS)], rtol=5e-3)
    for r, k in zip(rows, index, strict=True):
        assert lo + k * w - 1e-12 <= r["speed"] <= lo + (k + 1) * w + 1e-12
    assert levels(rows, "noise") == (["typical"], [0] * len(rows))  # few values: themselves


def test_survival_per_bin_and_the_worst_pair_cell_follow_the_falling_rule():
    rows = _rows()
    by_speed = axis_survival(rows, "speed")
    _, index = levels(rows, "speed")
    for k, (_, n, s) in enumerate(by_speed):
        mine = [r for r, i in zip(rows, index, strict=True) if i == k]
        assert n == len(mine) and s == sum(not r["fell"] for r in mine) / n
    assert by_speed[-1][2] < 0.2 < 0.8 < by_speed[0][2]  # the last bin is mostly > 1.6 m/s
    (x, y, xv, yv, n, s), *_ = worst_cells(rows)
    assert (x, y) == ("speed", "friction") and xv > 1.6 and yv < 0.4 and s == 0.0 and n >= 10


def test_the_falls_are_counted_by_cause_and_the_markdown_lists_them():
    rows = _rows()
    counts = cause_counts(rows)
    assert counts["slip"] == sum(r["fell"] and r["friction"] < 0.39 for r in rows)
    assert sum(counts.values()) == sum(r["fell"] for r in rows)
    md = "\n".join(breakdown_markdown(rows))
    assert f"| slip | {counts['slip']} |" in md and "`speed`" in md and "`friction`" in md
