"""The map figure draws a run's final map: a synthetic 10 cm step mapped on one side of x = 0.5 m, the
soles standing on both treads; the PNG is written and its edge cells are the step's."""

from __future__ import annotations

import numpy as np

from gaitshift.control.perception import EDGE_STEP, step_edges
from gaitshift.plots.perception import perception_figure


def test_the_map_figure_is_written_and_marks_the_step(tmp_path):
    n, r = 50, 0.04
    corner = np.array([-0.5, -1.0])
    x = corner[0] + (np.arange(n) + 0.5) * r
    heights = np.repeat(np.where(x > 0.5, 0.1, 0.0)[:, None], n, axis=1)
    seen = np.ones((n, n), bool)
    seen[:, :5] = False
    feet = np.zeros((20, 2, 3))
    feet[:, 0, :2], feet[:, 1, :2] = [0.2, 0.1], [0.9, -0.1]
    feet[:, 1, 2] = 0.1
    a = {"map_heights": heights, "map_seen": seen, "map_corner": corner, "map_resolution": np.array(r),
         "foot_pos": feet, "contact": np.ones((20, 2), bool)}  # fmt: skip
    out = perception_figure(a, tmp_path / "map.png", "step")
    assert out.stat().st_size > 10_000
    edges = step_edges(heights, seen, EDGE_STEP)
    assert edges.sum() == 2 * (n - 5) and np.all(np.abs(x[np.nonzero(edges)[0]] - 0.5) < r)
