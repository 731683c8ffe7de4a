"""The terrain of a plan built into the plant's MJCF: one static box per piece.

A flat piece ``x0..x1`` at height ``z`` (:class:`gaitshift.models.terrain.Piece`) is the box
``[x0, x1] x [-W, W] x [0, z]`` (W = :data:`HALF_WIDTH`). A ramp is a box whose top face is the
ramp, pitched by ``theta = atan(slope)`` about +y, ``max(z0, z1) + DEPTH`` thick so that its bottom
lies under the floor (world-body geoms never collide with each other, so the overlap is harmless).
A piece with a field of blocks (:mod:`gaitshift.models.blocks`) is one box per block,
``[xa, xb] x [ya, yb] x [0, z + dz]`` (eq. (1) there), and the piece's flat box beside the field on
either side (``|y| > w``).
Every terrain box copies the contact parameters of the floor (friction, solref, solimp, condim,
contype, conaffinity, priority): the feet meet the same ground everywhere.
"""

from __future__ import annotations

import math

import mujoco

from gaitshift.models.terrain import Piece, Terrain

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
        for j, (size, pos, quat) in enumerate(_boxes(p)):
            box = spec.worldbody.add_geom(
                name=f"{TERRAIN_PREFIX}{i}" + (f"_{j}" if p.blocks is not None else ""),
                type=mujoco.mjtGeom.mjGEOM_BOX,
                size=size,
                pos=pos,
                quat=quat,
                rgba=[0.55, 0.55, 0.6, 1.0] if j % 2 == 0 else [0.5, 0.5, 0.56, 1.0],
            )
            box.friction, box.solref, box.solimp = floor.friction, floor.solref, floor.solimp
            box.condim, box.contype, box.conaffinity = floor.condim, floor.contype, floor.conaffinity
            box.priority = floor.priority


Box = tuple[list[float], list[float], list[float]]


def _boxes(p: Piece) -> list[Box]:
    """The boxes of piece ``p`` as (half sizes, centre, quaternion w x y z): none on the floor."""
    if p.blocks is None:
        return _piece_box(p)
    w = p.blocks.half_width
    out = [_flat(p.x0, p.x1, ya, yb, p.z0) for ya, yb in ((-HALF_WIDTH, -w), (w, HALF_WIDTH))]
    out += [_flat(xa, xb, ya, yb, p.z0 + dz) for xa, xb, ya, yb, dz in p.blocks.cells(p.x0, p.x1)]
    return [b for b in out if b is not None]


def _flat(xa: float, xb: float, ya: float, yb: float, z: float) -> Box | None:
    """The box ``[xa, xb] x [ya, yb] x [0, z]``, or None when it has no top above the floor."""
    if z <= 0.0 or xb <= xa or yb <= ya:
        return None
    return (
        [0.5 * (xb - xa), 0.5 * (yb - ya), 0.5 * z],
        [0.5 * (xa + xb), 0.5 * (ya + yb), 0.5 * z],
        [1.0, 0.0, 0.0, 0.0],
    )


def _piece_box(p: Piece) -> list[Box]:
    """The one box of a piece without blocks: a tread, or a ramp pitched about +y (module docstring)."""
    if max(p.z0, p.z1) <= 0.0:
        return []  # on the floor
    theta = p.pitch
    half_len = 0.5 * math.hypot(p.x1 - p.x0, p.z1 - p.z0)
    thick = max(p.z0, p.z1) + DEPTH if p.z0 != p.z1 else p.z0
    top = ((p.x0 + p.x1) / 2, 0.0, (p.z0 + p.z1) / 2)
    normal = (-math.sin(theta), 0.0, math.cos(theta))
    centre = [top[k] - 0.5 * thick * normal[k] for k in range(3)]
    return [([half_len, HALF_WIDTH, 0.5 * thick], centre, [math.cos(-theta / 2), 0.0, math.sin(-theta / 2), 0.0])]
