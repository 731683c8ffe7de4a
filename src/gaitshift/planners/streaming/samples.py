"""The block of samples a streaming generator emits per call: the trajectory contract's columns.

Both generators emit a :class:`Samples`: the VHIP generator the contract's columns (``com_pos``,
``com_vel``, ``com_acc``, ``zmp``, ``phase``, ``contact``, ``foot_pos``, ``stiffness``), the
locomotion generator those plus ``foot_yaw``, ``foot_vel``, ``foot_acc``, ``heading``, ``gait``,
``step`` and ``step_type`` (:data:`gaitshift.planners.locomotion.samples.FIELDS`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from gaitshift.models.arrays import FloatArray

__all__ = ["Samples"]


@dataclass(frozen=True, eq=False)
class Samples:
    """A block of m consecutive samples (shapes as in :class:`gaitshift.Trajectory`).

    Attributes:
        t: (m,) times, s.
        cols: column name -> (m, *shape) array, each also read as an attribute (``s.com_pos``):
            e.g. com_pos, com_vel, com_acc (m, 3) in m, m/s, m/s^2; zmp (m, 3) m, NaN in flight;
            phase (m,) int8; contact (m, 2) bool [left, right]; foot_pos (m, 2, 3) m; stiffness (m,)
            s, NaN in flight.
        command: (m, k) command in force: (vx, vy) m/s (VHIP, k = 2) or (vx, vy, yaw rate) m/s,
            m/s, rad/s (locomotion, k = 3).
    """

    t: FloatArray
    cols: dict[str, npt.NDArray[Any]]
    command: FloatArray

    def __len__(self) -> int:
        return len(self.t)

    def __getattr__(self, name: str) -> npt.NDArray[Any]:
        cols: dict[str, npt.NDArray[Any]] = self.__dict__.get("cols", {})
        if name in cols:
            return cols[name]
        raise AttributeError(name)

    def tail(self, k: int) -> Samples:
        """The samples from the ``k``-th on (views, not copies)."""
        return Samples(self.t[k:], {c: v[k:] for c, v in self.cols.items()}, self.command[k:])

    @staticmethod
    def concat(blocks: list[Samples]) -> Samples:
        """The blocks one after the other (the block itself when there is one)."""
        if len(blocks) == 1:
            return blocks[0]
        return Samples(
            np.concatenate([b.t for b in blocks]),
            {k: np.concatenate([b.cols[k] for b in blocks]) for k in blocks[0].cols},
            np.concatenate([b.command for b in blocks]),
        )
