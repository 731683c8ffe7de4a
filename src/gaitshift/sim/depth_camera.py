"""The simulated depth camera: ray casts from the robot's camera site into the world's ground.

Each frame casts one ray per pixel (:meth:`gaitshift.robots.sensors.DepthCamera.rays`, camera frame)
from the site's true pose with ``mj_multiRay`` against the ground only (the geoms of the world body:
the floor, the terrain, the bumps; the robot's own links are not seen, as an elevation mapper's
robot-body filter removes them). A ray returns its range ``r`` when it hits within the camera's
``range``; the reading is

.. math:: \\tilde r = r + \\sigma(r)\\, n, \\quad n \\sim N(0, 1), \\quad \\sigma(r) = \\sigma_0 + k r^2

and the pixel is lost with probability ``dropout``. The frame holds the valid returns as points
``r~ d`` (M, 3) in the camera frame, ``d`` the pixel's unit ray: what a real depth camera's point cloud
is, so a real robot's cloud can take its place. A frame comes every ``round(1 / (rate dt))`` ticks
(the first at tick 0); between frames the camera reports nothing (None). Its draws come from their own
generator seeded with the run's seed, so noise on other sensors does not shift them.
"""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np

from gaitshift.robots.sensors import DEPTH_CAMERA_SITE, DepthCamera

__all__ = ["DepthCameraSim"]

#: salt of the camera's random stream (mixed with the run's seed)
STREAM = 0xD435


class DepthCameraSim:
    """One robot's depth camera in a simulated world (module docstring).

    Args:
        model: the world's ``MjModel`` (it carries the camera site). camera: the camera's facts.
        dt: the control period, s. seed: the run's seed.
    """

    def __init__(self, model: Any, camera: DepthCamera, dt: float, seed: int) -> None:
        self.model, self.camera = model, camera
        self.site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, DEPTH_CAMERA_SITE)
        self.rays = camera.rays()
        self.every = max(1, round(1.0 / (camera.rate * dt)))
        self.rng = np.random.default_rng([seed, STREAM])
        ground = model.geom_bodyid == 0
        self.groups = np.zeros(6, np.uint8)
        self.groups[np.unique(model.geom_group[ground])] = 1
        n = len(self.rays)
        self._geom = np.zeros(n, np.int32)
        self._dist = np.zeros(n)

    def read(self, d: Any, k: int) -> np.ndarray | None:
        """The frame of tick ``k`` (points (M, 3) m in the camera frame), or None between frames."""
        if k % self.every:
            return None
        m, cam = self.model, self.camera
        rot = d.site_xmat[self.site].reshape(3, 3)
        vec = self.rays @ rot.T
        n = len(self.rays)
        mujoco.mj_multiRay(
            m, d, d.site_xpos[self.site], vec.ravel(), self.groups, 1, -1, self._geom, self._dist, None, n, cam.range[1]
        )
        hit = self._geom >= 0
        hit[hit] = m.body_rootid[m.geom_bodyid[self._geom[hit]]] == 0  # the ground, not the robot
        r = self._dist.copy()
        sigma = cam.noise[0] + cam.noise[1] * r * r
        r += sigma * self.rng.standard_normal(n)
        keep = hit & (r >= cam.range[0]) & (r <= cam.range[1]) & (self.rng.random(n) >= cam.dropout)
        points: np.ndarray = r[keep, None] * self.rays[keep]
        return points
