"""The controller's perception: depth frames (camera frame) into an elevation map (world frame),
placed with the estimated pose (:mod:`.elevation_map`, :mod:`.perceiver`)."""

from gaitshift.control.perception.elevation_map import (
    EDGE_COLOR,
    EDGE_STEP,
    ElevationMap,
    MapSettings,
    seen_cells,
    step_edges,
)
from gaitshift.control.perception.perceiver import SCAN_COLOR, SCAN_POINTS, Perceiver, thin_scan

__all__ = [
    "EDGE_COLOR",
    "EDGE_STEP",
    "SCAN_COLOR",
    "SCAN_POINTS",
    "ElevationMap",
    "MapSettings",
    "Perceiver",
    "seen_cells",
    "step_edges",
    "thin_scan",
]
