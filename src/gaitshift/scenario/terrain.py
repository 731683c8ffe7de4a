"""The ``terrain:`` key of a scenario: pieces of ground on the floor (treads, steps, ramps).

Each piece spans ``x: [x0, x1]`` (m, every y) with its top going linearly from ``z[0]`` at x0 to
``z[1]`` at x1 (m, >= 0: the floor is z = 0); pieces are sorted along x and disjoint. Example, two
10 cm stairs up::

    terrain:
      - {x: [0.40, 0.65], z: [0.1, 0.1]}
      - {x: [0.65, 5.00], z: [0.2, 0.2]}

A flat piece may carry a field of random blocks (:mod:`gaitshift.models.blocks`): square blocks of
side ``size`` m whose tops lie ``+- height`` m about the piece's top (drawn from ``seed``), across
``|y| <= half_width`` m (default 1). The tops stay on or above the floor (``height`` <= the piece's
``z``). Such a ground is 2-D: the planner is never told it (``sim: {terrain: perceived}`` or
``blind``). Example, a 3 m field of 0.3 m blocks, +-4 cm about 4 cm::

    terrain:
      - {x: [1.0, 4.0], z: [0.04, 0.04], blocks: {size: 0.3, height: 0.04, seed: 0}}

The planner puts every foothold on it (z = the ground height under the sole centre plus the
foothold's own z); the simulator builds it (:mod:`gaitshift.models.terrain`, docs/simulation.md).
"""

from __future__ import annotations

import math
from typing import Annotated

from pydantic import Field, Strict, model_validator

from gaitshift.models.blocks import Blocks
from gaitshift.models.terrain import Piece, Terrain
from gaitshift.scenario.fields import Count, Length, Real, StrictModel

__all__ = ["MAX_SLOPE_DEG", "TerrainBlocks", "TerrainPiece", "terrain_of"]

#: steepest ramp a piece may have, degrees
MAX_SLOPE_DEG = 30.0
#: a terrain height, m (the floor is 0)
Height = Annotated[float, Strict(), Field(ge=0, le=10, allow_inf_nan=False)]


class TerrainBlocks(StrictModel):
    """A field of random blocks on a flat piece (module docstring): ``size`` m, ``height`` m, ``seed``,
    ``half_width`` m."""

    size: Annotated[float, Strict(), Field(ge=0.05, le=10, allow_inf_nan=False)]
    height: Height
    seed: Count
    half_width: Length = 1.0


class TerrainPiece(StrictModel):
    """One piece (module docstring): ``x`` = [x0, x1] m, ``z`` = top height [at x0, at x1] m; ``blocks``:
    a field of random blocks on it."""

    x: tuple[Real, Real]
    z: tuple[Height, Height]
    blocks: TerrainBlocks | None = None

    @model_validator(mode="after")
    def _shape(self) -> TerrainPiece:
        if not self.x[1] > self.x[0]:
            raise ValueError(f"x = {list(self.x)}: x1 must exceed x0")
        slope = abs(self.z[1] - self.z[0]) / (self.x[1] - self.x[0])
        if slope > math.tan(math.radians(MAX_SLOPE_DEG)):
            raise ValueError(f"a slope of at most {MAX_SLOPE_DEG:g} deg (this piece rises {slope:.3g} m per m)")
        b = self.blocks
        if b is not None and self.z[0] != self.z[1]:
            raise ValueError(f"blocks on a flat piece only (z = {list(self.z)})")
        if b is not None and b.height > self.z[0]:
            raise ValueError(
                f"blocks.height = {b.height}: at most the piece's z ({self.z[0]}): no block top below the floor"
            )
        return self


def check_pieces(pieces: tuple[TerrainPiece, ...]) -> None:
    """Raise ``ValueError`` when pieces overlap or are out of order along x."""
    for i in range(1, len(pieces)):
        if pieces[i].x[0] < pieces[i - 1].x[1]:
            raise ValueError(f"terrain pieces sorted along x and disjoint (piece {i} starts before piece {i - 1} ends)")


def terrain_of(pieces: tuple[TerrainPiece, ...]) -> Terrain:
    """The :class:`~gaitshift.models.terrain.Terrain` of the scenario's pieces."""
    return Terrain(tuple(Piece(p.x[0], p.x[1], p.z[0], p.z[1], _blocks(p.blocks)) for p in pieces))


def _blocks(b: TerrainBlocks | None) -> Blocks | None:
    """The model's :class:`Blocks` of a piece's ``blocks:`` key."""
    return None if b is None else Blocks(b.size, b.height, b.seed, b.half_width)


def world_ground(scenario: object) -> Terrain | None:
    """The ground a scenario's world is built on (its ``terrain:`` pieces, whatever the planner is told),
    or None for a scenario without one (a flat floor)."""
    pieces = getattr(scenario, "terrain", ())
    return terrain_of(pieces) if pieces else None
