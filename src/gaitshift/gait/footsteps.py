"""Footholds: the two standing feet a plan starts on, stride profiles, and the closing step.

Footstep indices 0 and 1 are the initial left and right feet; each step adds one foothold; a closing
step places the trailing foot beside the last one (same heading and height, ``step_width`` apart).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from gaitshift.models.terrain import Terrain
from gaitshift.trajectory.contract import LEFT, RIGHT


@dataclass(frozen=True)
class Footstep:
    """A foothold: sole centre (x, y, z) in m, yaw in rad, side 0 left / 1 right."""

    x: float
    y: float
    z: float
    yaw: float
    side: int


def stride_profile(n_steps: int, max_stride: float, accelerate: int, decelerate: int) -> np.ndarray:
    """Forward stride of each step, m, shape (n_steps,): a trapezoid.

    The stride ramps linearly up over ``accelerate`` steps (max * k/(accelerate+1), k = 1..),
    holds ``max_stride``, and ramps down symmetrically over the last ``decelerate`` steps. Where the
    ramps overlap (short plans) the smaller value wins.
    """
    i = np.arange(1, n_steps + 1, dtype=float)
    up = np.minimum(i / (accelerate + 1), 1.0) if accelerate > 0 else np.ones(n_steps)
    j = n_steps + 1 - i
    down = np.minimum(j / (decelerate + 1), 1.0) if decelerate > 0 else np.ones(n_steps)
    return max_stride * np.minimum(up, down)


def initial_feet(step_width: float) -> list[Footstep]:
    """The two standing feet a plan starts on: left at (0, +w/2, 0), right at (0, -w/2, 0), yaw 0."""
    return [Footstep(0.0, step_width / 2, 0.0, 0.0, LEFT), Footstep(0.0, -step_width / 2, 0.0, 0.0, RIGHT)]


def closing_footstep(last: Footstep, step_width: float) -> Footstep:
    """The foothold beside ``last`` (same heading and height) on the other side."""
    sign = 1.0 if last.side == RIGHT else -1.0  # the new foot is on the other side
    return Footstep(
        last.x - sign * step_width * math.sin(last.yaw),
        last.y + sign * step_width * math.cos(last.yaw),
        last.z,
        last.yaw,
        1 - last.side,
    )


def footsteps_from_profile(
    n_steps: int,
    first_swing: int,
    strides: np.ndarray,
    step_width: float,
    yaw_rate: float = 0.0,
    step_height: float = 0.0,
) -> list[Footstep]:
    """Footholds for ``n_steps`` steps plus the closing step, after the two initial feet.

    The path centre advances by ``strides[i]`` along the heading, which turns by ``yaw_rate`` rad per
    step; each foothold sits ``step_width/2`` to its side of the path and ``step_height`` higher per step.
    """
    feet = initial_feet(step_width)
    last = feet[1 - first_swing]  # the stance foot of the first step
    cx = cy = cz = heading = 0.0
    side = first_swing
    for i in range(n_steps):
        heading += yaw_rate
        cx += strides[i] * math.cos(heading)
        cy += strides[i] * math.sin(heading)
        cz += step_height
        sign = 1.0 if side == LEFT else -1.0
        last = Footstep(
            cx - sign * step_width / 2 * math.sin(heading),
            cy + sign * step_width / 2 * math.cos(heading),
            cz,
            heading,
            side,
        )
        feet.append(last)
        side = 1 - side
    feet.append(closing_footstep(last, step_width))
    return feet


def on_terrain(feet: list[Footstep], terrain: Terrain, sole: tuple[float, float]) -> list[Footstep]:
    """The footholds set on ``terrain``: each z becomes the ground height under the sole centre plus
    the foothold's own z (m). ``sole`` is (length, width), m.

    Raises:
        ValueError: "i: ..." for the first foothold ``i`` (0, 1: the initial feet) whose sole lies
            across a break of the terrain (a stair edge, the foot of a ramp).
    """
    if terrain.flat:
        return feet
    out = []
    for i, f in enumerate(feet):
        edge = terrain.sole_fits(f.x, f.yaw, *sole)
        if edge is not None:
            raise ValueError(f"{i}: the sole at x = {f.x:.3f} m lies across the terrain break at x = {edge:.3f} m")
        out.append(Footstep(f.x, f.y, f.z + float(terrain.height(f.x)), f.yaw, f.side))
    return out
