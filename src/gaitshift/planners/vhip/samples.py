"""The block of samples a streaming generator emits per call (the columns of the trajectory contract)."""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from gaitshift.models.arrays import BoolArray, FloatArray, Int8Array

__all__ = ["Samples"]


@dataclass(frozen=True, eq=False)
class Samples:
    """A block of m consecutive samples (shapes as in :class:`gaitshift.Trajectory`).

    Attributes:
        t: (m,) times, s.
        com_pos, com_vel, com_acc: (m, 3) CoM position (m), velocity (m/s), acceleration (m/s^2).
        zmp: (m, 3) ZMP, m; NaN in flight.
        phase: (m,) int8 contact phase (DS, SS, FLIGHT).
        contact: (m, 2) bool, [left, right] sole on the ground.
        foot_pos: (m, 2, 3) sole centres [left, right], m.
        command: (m, 2) commanded speed in force, m/s.
        stiffness: (m,) sqrt(z / (z'' + g)) in support (s), NaN in flight.
    """

    t: FloatArray
    com_pos: FloatArray
    com_vel: FloatArray
    com_acc: FloatArray
    zmp: FloatArray
    phase: Int8Array
    contact: BoolArray
    foot_pos: FloatArray
    command: FloatArray
    stiffness: FloatArray

    def __len__(self) -> int:
        return len(self.t)

    @staticmethod
    def concat(blocks: list[Samples]) -> Samples:
        """The blocks one after the other."""
        return Samples(**{f.name: np.concatenate([getattr(b, f.name) for b in blocks]) for f in fields(Samples)})
