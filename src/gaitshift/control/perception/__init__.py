"""The controller's perception: depth frames (camera frame) into an elevation map (world frame),
placed with the estimated pose (:mod:`.elevation_map`, :mod:`.perceiver`)."""

from gaitshift.control.perception.elevation_map import ElevationMap, MapSettings, step_edges
from gaitshift.control.perception.perceiver import Perceiver

__all__ = ["ElevationMap", "MapSettings", "Perceiver", "step_edges"]
