"""The report counts what the rows say: a survival cell is the share of its cases that did not fall
(error rows excluded), the per-robot table pools every case of a robot, and the files are written."""

from __future__ import annotations

import itertools
import math

import numpy as np

from gaitshift.campaign.figures import survival_grid
from gaitshift.campaign.report import robot_table, write_report
from gaitshift.campaign.store import SCHEMA, Store


def _rows() -> list[dict]:
    """3 speeds x 3 pushes x 2 masses x 2 frictions; a case falls when push * mass / friction > 12,
    so every cell's survival is known in closed form; one extra case is an error row."""
    rows = []
    for v, p, m, mu in itertools.product((0.3, 0.5, 0.7), (0.0, 10.0, 20.0), (1.0, 1.2), (0.5, 1.0)):
        fell = p * m / mu > 12
        row = dict.fromkeys(SCHEMA.names) | {"task": "simulate", "speed": v, "push_impulse": p, "mass_scale": m}
        row |= {"friction": mu, "fell": fell, "t_fall": 1.0 + v if fell else None, "wall_time": 2.0}
        row |= {"gaitshift_version": "x", "case_hash": f"{v}-{p}-{m}-{mu}", "robot": "g1"}
        rows.append(row)
    rows.append(dict.fromkeys(SCHEMA.names) | {"case_hash": "err", "error": "infeasible", "robot": "g1"})
    return rows


def test_survival_cells_match_the_closed_form():
    """Cell (push, speed) = share of the 4 (mass, friction) cases with push * mass / friction <= 12."""
    rows = _rows()
    g = survival_grid(rows, "speed", "push_impulse")
    assert g is not None and g.xs == [0.3, 0.5, 0.7] and g.ys == [0.0, 10.0, 20.0]
    for i, p in enumerate(g.ys):
        alive = np.mean([p * m / mu <= 12 for m in (1.0, 1.2) for mu in (0.5, 1.0)])
        assert np.all(g.rate[i] == alive) and np.all(g.n[i] == 4)
    assert survival_grid(rows, "speed", "latency") is None  # latency is not swept: no map


def test_robot_table_and_files(tmp_path):
    """The table pools 36 run cases and 1 error; the report writes both maps, the histogram, the summary."""
    store = Store(tmp_path)
    store.start("task: simulate\n")
    for r in _rows():
        store.write({"row": r, "motion": None})
    (t,) = robot_table(store.table().to_pylist())
    falls = [r for r in _rows() if r["fell"]]
    assert (t["cases"], t["errors"]) == (37, 1)
    assert math.isclose(t["survival_pct"], 100 * (36 - len(falls)) / 36)
    files = write_report(tmp_path)
    names = {f.name for f in files}
    assert names == {"survival_speed_push.png", "survival_mass_friction.png", "fall_times.png", "summary.md"}
    text = (tmp_path / "report" / "summary.md").read_text()
    assert "1800 cases per hour per core" in text and "| g1 | 37 | 1 |" in text
