"""The terrain of a plan built into the plant's MJCF: one static box per piece.

A flat piece ``x0..x1`` at height ``z`` (:class:`gaitshift.models.terrain.Piece`) is the box
``[x0, x1] x [-W, W] x [0, z]`` (W = :data:`HALF_WIDTH`). A ramp is a box whose top face is the
ramp, pitched by ``theta = atan(slope)`` about +y, ``max(z0, z1) + DEPTH`` thick so that its bottom
lies under the floor (world-body geoms never collide with each other, so the overlap is harmless).
Every terrain box copies the contact parameters of the floor (friction, solref, solimp, condim,
contype, conaffinity, priority): the feet meet the same ground everywhere.
"""

from __future__ import annotations

import math

import mujoco

from gaitshift.models.terrain import Terrain

__all__ = ["DEPTH", "HALF_WIDTH", "TERRAIN_PREFIX", "add_terrain"]

#: half width of every piece across the walking direction, m
HALF_WIDTH = 5.0
#: a ramp box reaches this far below the floor, m
DEPTH = 0.05
#: geom name prefix of the terrain boxes (terrain0, terrain1, ...)
TERRAIN_PREFIX = "terrain"


def add_terrain(spec: mujoco.MjSpec, terrain: Terrain) -> None:
    """Add the boxes of ``terrain`` to the world body of ``spec`` (module docstring); the spec must
    hold a floor plane already."""
    floor = next(g for g in spec.worldbody.geoms if g.type == mujoco.mjtGeom.mjGEOM_PLANE)
    for i, p in enumerate(terrain.pieces):
        if max(p.z0, p.z1) <= 0.0:
            continue  # on the floor
        theta = p.pitch
        half_len = 0.5 * math.hypot(p.x1 - p.x0, p.z1 - p.z0)
        thick = max(p.z0, p.z1) + DEPTH if p.z0 != p.z1 else p.z0
        top = ((p.x0 + p.x1) / 2, 0.0, (p.z0 + p.z1) / 2)
        normal = (-math.sin(theta), 0.0, math.cos(theta))
        centre = [top[k] - 0.5 * thick * normal[k] for k in range(3)]
        box = spec.worldbody.add_geom(
            name=f"{TERRAIN_PREFIX}{i}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[half_len, HALF_WIDTH, 0.5 * thick],
            pos=centre,
            quat=[math.cos(-theta / 2), 0.0, math.sin(-theta / 2), 0.0],
            rgba=[0.55, 0.55, 0.6, 1.0],
        )
        box.friction, box.solref, box.solimp = floor.friction, floor.solref, floor.solimp
        box.condim, box.contype, box.conaffinity = floor.condim, floor.contype, floor.conaffinity
        box.priority = floor.priority
