"""The depth frames into the elevation map, on the controller's side of the truth barrier.

A frame's points ``p_c`` (M, 3) m come in the camera frame (:class:`~gaitshift.control.frames.SensorFrame`
``depth_points``). The controller places them with the camera site's pose in ITS OWN model at the
estimated state (``R``, ``o``: the estimate's drift and tilt error go into the map, as on a robot):

.. math:: p_w = o + R\\, p_c                                                               (1)

Each point's height variance is the range error along the ray projected on the vertical:

.. math:: R_k = (\\sigma(r_k)\\, d_{z,k})^2 + \\epsilon, \\quad
          \\sigma(r) = \\sigma_0 + k r^2, \\quad d_z = (R\\, p_c)_z / r                       (2)

The map is robot-centric (Fankhauser et al. 2014): it lives in the estimated frame, where the feet
are placed too. The estimate's absolute drift moves that whole frame, not one point in it, so it is
not a point's error; what the drift does between seeing a cell and stepping on it is the map's
process noise (eq. (2) of :mod:`.elevation_map`). (Adding the base's position variance to every
point, as before 2026-11-28, made the far ground unusable once the estimate had walked a few metres:
3-4 cm of position standard deviation on every point of a run at 1.5 m/s.)

(``sigma_0``, ``k``: the camera's ``noise`` in the robot YAML; ``epsilon`` = 1e-8 m^2 keeps an exact
camera's points finite in eq. (1) of :mod:`.elevation_map`). Before fusing, the map ages by the time
since the last frame and re-centres on the estimated base.
"""

from __future__ import annotations

import math
import time
from typing import Any

import mujoco
import numpy as np

from gaitshift.control.perception.elevation_map import ElevationMap, MapSettings
from gaitshift.robots.sensors import DEPTH_CAMERA_SITE, DepthCamera

__all__ = ["SCAN_COLOR", "SCAN_POINTS", "Perceiver", "thin_scan"]

#: the smallest height variance of a point, m^2 (eq. (2))
MIN_VARIANCE = 1e-8
#: the most points of a scan a picture or the run's log keeps (:func:`thin_scan`)
SCAN_POINTS = 1024
#: the colour (RGB) the pictures draw the scan in (browser view, Rerun)
SCAN_COLOR = (235, 60, 200)


class Perceiver:
    """Depth frames into the map (module docstring).

    Args:
        model: the controller's ``MjModel`` (it carries the camera site). camera: the camera's facts.
        settings: the map's size and resolution.

    Attributes:
        map: the elevation map. frames: frames fused. last_t: the last frame's time, s. scan: the last
        frame's points (M, 3) m placed by eq. (1), in the world frame as the controller estimates it
        (what the browser view and the run's log draw: the brain's view of the scan, never the truth).
        cost_us: the last frame's cost, µs.
    """

    def __init__(self, model: Any, camera: DepthCamera, settings: MapSettings | None = None) -> None:
        self.site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, DEPTH_CAMERA_SITE)
        self.camera = camera
        self.map = ElevationMap(settings)
        self.last_t: float | None = None
        self.scan = np.zeros((0, 3))  # the last frame's points placed by eq. (1): world frame (estimated), m
        self.frames = 0
        self.cost_us = 0.0  # the last frame's cost, µs

    def frame(self, t: float, points: np.ndarray, data: Any) -> None:
        """Fuse the frame ``points`` (M, 3) m (camera frame) taken at ``t`` s, with the camera pose of
        ``data`` (the controller's ``MjData`` at the estimated state, kinematics done)."""
        t0 = time.perf_counter()
        rot = data.site_xmat[self.site].reshape(3, 3)
        ray = points @ rot.T
        world = data.site_xpos[self.site] + ray
        r = np.linalg.norm(points, axis=1)
        dz = np.divide(ray[:, 2], r, out=np.zeros_like(r), where=r > 0)
        sigma = self.camera.noise[0] + self.camera.noise[1] * r * r
        var = (sigma * dz) ** 2 + MIN_VARIANCE
        m = self.map
        if self.last_t is not None:
            m.age(max(0.0, t - self.last_t))
        m.recenter(data.qpos[:2])
        m.fuse(world, var)
        self.last_t, self.scan = t, world
        self.frames += 1
        self.cost_us = (time.perf_counter() - t0) * 1e6


def thin_scan(points: np.ndarray) -> np.ndarray:
    """A scan's points (M, 3) m as float32, at most :data:`SCAN_POINTS` of them: every
    ``ceil(M / SCAN_POINTS)``-th (what a picture or the run's log keeps of :attr:`Perceiver.scan`)."""
    return np.asarray(points[:: max(1, math.ceil(len(points) / SCAN_POINTS))], dtype=np.float32)
