"""A controller's elevation map that saw a terrain exactly (tests/control): every cell holds the true
ground's height at its centre, in the plane (:meth:`gaitshift.models.terrain.Terrain.height_xy`)."""

from __future__ import annotations

import numpy as np

from gaitshift.control.perception import ElevationMap, MapSettings
from gaitshift.models.terrain import Terrain


def seen_map(truth: Terrain, centre: float, size: float = 4.0, resolution: float = 0.04, variance: float = 1e-6):
    """A ``size`` m map of ``resolution`` m cells centred at x = ``centre`` m, y = 0, every cell seen at
    the ground under its centre with ``variance`` m^2."""
    emap = ElevationMap(MapSettings(size=size, resolution=resolution))
    emap.recenter(np.array([centre, 0.0]))
    xy = emap.centres().reshape(-1, 2)
    emap.fuse(np.column_stack([xy, truth.height_xy(xy[:, 0], xy[:, 1])]), np.full(len(xy), variance))
    return emap
