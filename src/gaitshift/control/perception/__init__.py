"""The controller's perception: depth frames (camera frame) into an elevation map (world frame),
placed with the estimated pose (:mod:`.elevation_map`, :mod:`.perceiver`)."""

from gaitshift.control.perception.elevation_map import EDGE_STEP, ElevationMap, MapSettings, seen_cells, step_edges
from gaitshift.control.perception.perceiver import Perceiver

__all__ = ["EDGE_STEP", "ElevationMap", "MapSettings", "Perceiver", "seen_cells", "step_edges"]
