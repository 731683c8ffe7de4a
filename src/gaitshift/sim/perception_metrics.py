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
* ``frames``: depth frames fused;
* ``edge_distance_min``, ``edge_distance_median``: m, at every stance (the middle tick of each contact
  of at least :data:`MIN_STANCE` s: a toe scuffing an edge in a swing is no stance), from the true
  sole to the nearest step edge of the true terrain in the plane (a stair edge, a block's side:
  :meth:`gaitshift.models.terrain.Terrain.edge_distance`, the sole a ``length`` x ``width`` rectangle
  along the world axes): negative when the sole lies across the edge. Only with a terrain that has
  step edges.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gaitshift.models.terrain import Terrain

__all__ = ["MIN_STANCE", "edge_distances", "perception_metrics", "stances"]

#: s, the shortest contact counted as a stance by the edge distance
MIN_STANCE = 0.05


def perception_metrics(
    a: dict[str, np.ndarray],
    frames: int,
    ground: Terrain | None = None,
    sole: tuple[float, float] = (0.0, 0.0),
    dt: float | None = None,
) -> dict[str, Any]:
    """``{"perception": {...}}`` of a run's arrays (module docstring) on the true ``ground`` with soles
    ``sole`` (length, width) m, ticks ``dt`` s apart (None: no edge distance); ``{}`` without a map."""
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
    if dt is not None:  # the edge distance, at each stance of ``dt`` s ticks
        out.update(edge_distances(stances(stance, dt), a["foot_pos"][:, :, :2], ground, sole))
    return {"perception": out}


def stances(contact: np.ndarray, dt: float) -> np.ndarray:
    """(N, 2) bool: the middle tick of every contact run of ``contact`` (N, 2) lasting at least
    :data:`MIN_STANCE` s at ``dt`` s per tick."""
    out = np.zeros_like(contact, dtype=bool)
    for s in range(contact.shape[1]):
        c = np.r_[False, contact[:, s].astype(bool), False]
        start, end = np.flatnonzero(c[1:] & ~c[:-1]), np.flatnonzero(~c[1:] & c[:-1])
        long = (end - start) * dt >= MIN_STANCE
        out[(start[long] + end[long] - 1) // 2, s] = True
    return out


def edge_distances(
    at: np.ndarray, xy: np.ndarray, ground: Terrain | None, sole: tuple[float, float]
) -> dict[str, float]:
    """``edge_distance_min`` and ``_median`` (module docstring) of the soles at the ticks ``at`` (N, 2)
    bool with true sole centres ``xy`` (N, 2, 2) m and ``sole`` (length, width) m; ``{}`` without step
    edges or such ticks."""
    if ground is None or not at.any():
        return {}
    p = xy[at]
    d = ground.edge_distance(p[:, 0], p[:, 1], 0.5 * sole[0], 0.5 * sole[1])
    if not np.isfinite(d).all():  # no step edge counts (none, or all lower than the least step)
        return {}
    return {"edge_distance_min": float(d.min()), "edge_distance_median": float(np.median(d))}
