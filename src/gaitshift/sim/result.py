"""The result of a closed-loop run: the logged arrays, the fall, the metadata and the metrics."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.common.atomic import atomic_path
from gaitshift.common.jsonsafe import finite_json
from gaitshift.errors import InputError
from gaitshift.trajectory.contract import Trajectory


@dataclass
class SimResult:
    """Logged arrays (per control tick) and the summary.

    File keys (``save``): the arrays (``t``, ``qpos``, ``qvel``, ``tau``, ``com_pos``, ``com_ref`` (the
    reference tracked: plan + capture-point shift), ``com_vel``, ``com_vel_ref``, ``contact`` (measured),
    ``contact_ref``, ``stance`` (controller), ``grf`` (N, 2, 3) measured, ``grf_ref`` (QP), ``foot_pos``,
    ``foot_ref``, ``angmom``, ``com_shift``, ``plan_index``, ``qp_ok``, ``push_force``, ``legs_touch``,
    ``feet_overlap``; see
    :mod:`gaitshift.sim.log`; and, not per tick, the scans the controller fused ``scan_t``,
    ``scan_points``, ``scan_frame`` and the footholds each time the plan changed them ``footholds_t``,
    ``footholds``, ``footholds_side``, ``footholds_set``, and the elevation map's snapshots ``map_t``,
    ``map_cells``, ``map_cells_edge``, ``map_cells_set``), ``fell``, ``fall_time`` (s; -1 when the robot
    did not fall) and ``meta`` (strict JSON, with the metrics). ``plan``: the run's plan as the loop tracked
    it (:meth:`gaitshift.control.controller.Controller.whole_plan`; not saved, None when loaded).
    """

    arrays: dict[str, np.ndarray]
    fell: bool
    fall_time: float
    fall_reason: str
    meta: dict[str, Any]
    metrics: dict[str, Any]
    plan: Trajectory | None = None

    def save(self, path: str | Path) -> Path:
        """Write the run to ``path`` (.npz), atomically.

        Raises:
            InputError: ``path`` does not end in .npz.
        """
        path = Path(path)
        if path.suffix.lower() != ".npz":
            raise InputError("out", str(path), "a file ending in .npz")
        meta = dict(self.meta, metrics=self.metrics, fall_reason=self.fall_reason)
        payload: dict[str, Any] = {
            **self.arrays,
            "fell": np.array(self.fell),
            "fall_time": np.array(self.fall_time if self.fell else -1.0),
            "meta": np.array(json.dumps(finite_json(meta), allow_nan=False)),
        }
        with atomic_path(path) as tmp, open(tmp, "wb") as fh:
            np.savez_compressed(fh, **payload)
        return path
