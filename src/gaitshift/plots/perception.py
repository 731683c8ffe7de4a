"""The controller's elevation map at the end of a run (issue 29): ``sim_perception.png``.

From a run's arrays (the ``.npz`` that ``gaitshift simulate --out`` writes for a robot with a depth
camera, :class:`gaitshift.sim.log.PerceptionLog`): the map as the run ended (``map_heights``,
``map_seen``, ``map_corner``, ``map_resolution``), the true sole positions ``foot_pos`` and the truth's
``contact``. Two panels:

* top view: the map's heights (unseen cells blank), the cells on an edge (a neighbour more than
  :data:`gaitshift.control.perception.EDGE_STEP` m away, :func:`gaitshift.control.perception.step_edges`)
  in grey, and the true sole centres where each sole stood;
* side view: along x, the map's cells within :data:`BAND` m of the path's centre line (dots) and the
  true soles' heights while they stood (the ground they stood on);
* in both, the plan's footholds when given (with ``--terrain perceived``: the ones chosen on the map).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from gaitshift.control.perception import EDGE_STEP, step_edges
from gaitshift.plots.files import save_figure

__all__ = ["BAND", "perception_figure"]

#: half-width of the side view's band around the path's centre line, m
BAND = 0.15


def perception_figure(a: dict[str, Any], path: str | Path, title: str = "", footholds: Any = None) -> Path:
    """Draw the map of the run's arrays ``a`` (module docstring) into ``path`` (PNG), with the plan's
    ``footholds`` (M, >= 3: x, y, z m; the plan as it ended: with ``--terrain perceived``, chosen on the map)
    as crosses when given."""
    h, seen = np.asarray(a["map_heights"]), np.asarray(a["map_seen"], dtype=bool)
    r, corner = float(a["map_resolution"]), np.asarray(a["map_corner"], dtype=float)
    n = len(h)
    extent = (corner[0], corner[0] + n * r, corner[1], corner[1] + n * r)
    stood = np.asarray(a["contact"], dtype=bool)
    feet = np.asarray(a["foot_pos"])
    fig, (top, side) = plt.subplots(2, 1, figsize=(9, 7.5), height_ratios=(2, 1))
    shown = np.ma.masked_array(h, ~seen)
    im = top.imshow(shown.T, origin="lower", extent=extent, cmap="viridis", interpolation="nearest")
    edge = np.ma.masked_array(np.ones_like(h), ~step_edges(h, seen, EDGE_STEP))
    top.imshow(edge.T, origin="lower", extent=extent, cmap="gray", vmin=0, vmax=2, interpolation="nearest")
    for s, colour in ((0, "tab:red"), (1, "tab:blue")):
        p = feet[stood[:, s], s]
        top.plot(p[:, 0], p[:, 1], ".", ms=2, color=colour, label=("left" if s == 0 else "right") + " sole (truth)")
    plan = None if footholds is None else np.asarray(footholds, dtype=float)
    if plan is not None:
        top.plot(plan[:, 0], plan[:, 1], "x", ms=6, color="white", mec="black", label="planned footholds")
    top.set_aspect("equal")
    top.set_xlabel("x (m)")
    top.set_ylabel("y (m)")
    top.legend(loc="upper left", fontsize=7)
    fig.colorbar(im, ax=top, label="map height (m)")
    centre = np.asarray(corner[1] + (np.arange(n) + 0.5) * r)
    mid = float(np.median(feet[:, :, 1]))
    rows = np.abs(centre - mid) <= BAND
    xs = corner[0] + (np.arange(n) + 0.5) * r
    xx = np.repeat(xs[:, None], rows.sum(), axis=1)
    band_seen = seen[:, rows]
    side.plot(xx[band_seen], h[:, rows][band_seen], ".", ms=2, color="tab:green", label="map cells near the path")
    for s in (0, 1):
        p = feet[stood[:, s], s]
        side.plot(p[:, 0], p[:, 2], "k.", ms=2, label="soles standing (truth)" if s == 0 else None)
    if plan is not None:
        side.plot(plan[:, 0], plan[:, 2], "x", ms=6, color="tab:orange", label="planned footholds")
    side.set_xlabel("x (m)")
    side.set_ylabel("z (m)")
    side.legend(fontsize=7)
    fig.suptitle(title, fontsize=9)
    return save_figure(fig, path)
