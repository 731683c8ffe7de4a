"""How right the controller's elevation map was under the feet (``simulate --json`` ``perception``).

Over the ticks a sole stands on the ground (the truth's ``contact``), its true sole centre lies on
the ground, so its height ``z`` is the ground's there; the map's height ``h`` at the same point
(:class:`gaitshift.sim.log.PerceptionLog`) is compared with it:

* ``map_error_median``, ``map_error_p95``: of ``|h - z|`` m over the stance ticks whose cell the map
  had seen;
* ``map_coverage``: the share of stance ticks whose cell the map had seen (a blind spot under the
  feet lowers it: the camera looks ahead, and a cell stays known once seen);
* ``frames``: depth frames fused.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["perception_metrics"]


def perception_metrics(a: dict[str, np.ndarray], frames: int) -> dict[str, Any]:
    """``{"perception": {...}}`` of a run's arrays (module docstring); ``{}`` without a map."""
    if "map_height" not in a:
        return {}
    stance = a["contact"].astype(bool)
    known = stance & a["map_known"]
    err = np.abs(a["map_height"] - a["foot_pos"][:, :, 2])[known]
    out: dict[str, Any] = {"frames": int(frames), "map_coverage": float(known.sum() / max(1, stance.sum()))}
    if len(err):
        out["map_error_median"] = float(np.median(err))
        out["map_error_p95"] = float(np.percentile(err, 95))
    return {"perception": out}
