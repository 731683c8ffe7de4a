"""How right the controller's elevation map was under the feet (``simulate --json`` ``perception``).

Over the ticks a sole stands on the ground (the truth's ``contact``), its true sole centre lies on
the ground, so its height ``z`` is the ground's there; the map's height ``h`` at the same point
(:class:`gaitshift.sim.log.PerceptionLog`) is compared with it:

* ``map_error_median``, ``map_error_p95``: of ``|h - z|`` m over the stance ticks whose cell the map
  had seen (the map is placed with the estimated pose, so this error carries the estimator's drift);
* ``frame_error_median``, ``frame_error_p95``: the same in the controller's own (estimated) frame,
  ``|h - (z + zhat_b - z_b)|`` with ``zhat_b - z_b`` the estimate's base-height error at that
  tick: how far the map is from where the controller believes its standing sole is, which is what a
  foothold chosen from the map meets (the sole-to-base kinematics comes from the joint encoders);
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
    diff = a["map_height"] - a["foot_pos"][:, :, 2]
    out: dict[str, Any] = {"frames": int(frames), "map_coverage": float(known.sum() / max(1, stance.sum()))}
    errors = {"map_error": diff}
    if "est_qpos" in a:
        errors["frame_error"] = diff - (a["est_qpos"][:, 2] - a["qpos"][:, 2])[:, None]
    for name, e in errors.items():
        err = np.abs(e[known])
        if len(err):
            out[f"{name}_median"] = float(np.median(err))
            out[f"{name}_p95"] = float(np.percentile(err, 95))
    return {"perception": out}
