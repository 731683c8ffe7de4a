"""The ``terrain:`` key of a scenario: pieces of ground on the floor (treads, steps, ramps).

Each piece spans ``x: [x0, x1]`` (m, every y) with its top going linearly from ``z[0]`` at x0 to
``z[1]`` at x1 (m, >= 0: the floor is z = 0); pieces are sorted along x and disjoint. Example, two
10 cm stairs up::

    terrain:
      - {x: [0.40, 0.65], z: [0.1, 0.1]}
      - {x: [0.65, 5.00], z: [0.2, 0.2]}

The planner puts every foothold on it (z = the ground height under the sole centre plus the
foothold's own z); the simulator builds it (:mod:`gaitshift.models.terrain`, docs/simulation.md).
"""

from __future__ import annotations

import math
from typing import Annotated

from pydantic import Field, Strict, model_validator

from gaitshift.models.terrain import Piece, Terrain
from gaitshift.scenario.fields import Real, StrictModel

__all__ = ["MAX_SLOPE_DEG", "TerrainPiece", "terrain_of"]

#: steepest ramp a piece may have, degrees
MAX_SLOPE_DEG = 30.0
#: a terrain height, m (the floor is 0)
Height = Annotated[float, Strict(), Field(ge=0, le=10, allow_inf_nan=False)]


class TerrainPiece(StrictModel):
    """One piece (module docstring): ``x`` = [x0, x1] m, ``z`` = top height [at x0, at x1] m."""

    x: tuple[Real, Real]
    z: tuple[Height, Height]

    @model_validator(mode="after")
    def _shape(self) -> TerrainPiece:
        if not self.x[1] > self.x[0]:
            raise ValueError(f"x = {list(self.x)}: x1 must exceed x0")
        slope = abs(self.z[1] - self.z[0]) / (self.x[1] - self.x[0])
        if slope > math.tan(math.radians(MAX_SLOPE_DEG)):
            raise ValueError(f"a slope of at most {MAX_SLOPE_DEG:g} deg (this piece rises {slope:.3g} m per m)")
        return self


def check_pieces(pieces: tuple[TerrainPiece, ...]) -> None:
    """Raise ``ValueError`` when pieces overlap or are out of order along x."""
    for i in range(1, len(pieces)):
        if pieces[i].x[0] < pieces[i - 1].x[1]:
            raise ValueError(f"terrain pieces sorted along x and disjoint (piece {i} starts before piece {i - 1} ends)")


def terrain_of(pieces: tuple[TerrainPiece, ...]) -> Terrain:
    """The :class:`~gaitshift.models.terrain.Terrain` of the scenario's pieces."""
    return Terrain(tuple(Piece(p.x[0], p.x[1], p.z[0], p.z[1]) for p in pieces))


def world_ground(scenario: object) -> Terrain | None:
    """The ground a scenario's world is built on (its ``terrain:`` pieces, whatever the planner is told),
    or None for a scenario without one (a flat floor)."""
    pieces = getattr(scenario, "terrain", ())
    return terrain_of(pieces) if pieces else None
