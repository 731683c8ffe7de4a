"""Swing feet of the VHIP generator: lift-offs planned before their footholds, on the shared tracker.

Each foot rests at its last foothold ("home") until it lifts off. The step planner knows a foot's
lift-off (the take-off that ends its stance, :meth:`FootTracks.set_lift`) before the foothold it swings
to (:meth:`FootTracks.swing_to`); the swing itself is a :class:`gaitshift.gait.swing_track.Swing`, the
tracker the locomotion generator uses too: from rest it is the minimum-jerk horizontal blend and the
height sextic through the apex ``clearance`` above the higher sole of :mod:`gaitshift.gait.swing`.
A redirect (:meth:`FootTracks.redirect`, a re-plan) starts a new quintic from the foot's current
position, velocity and acceleration, so the foot reference stays C2 (no velocity jump); the height
keeps its sextic unless the touchdown moves. Swings that ended before the next emitted sample are
forgotten (:meth:`FootTracks.prune`), so the tracks stay bounded. Poses are (x, y, z) with yaw 0.
"""

from __future__ import annotations

import numpy as np

from gaitshift.gait.swing_track import FootTrack, Swing
from gaitshift.models.arrays import FloatArray, IntArray

__all__ = ["FootTracks"]


def _pose(p: FloatArray) -> FloatArray:
    """(x, y, z) -> (x, y, z, yaw 0)."""
    return np.array([p[0], p[1], p[2], 0.0])


class FootTracks:
    """The planned swings of both feet and the foot positions they give.

    Args:
        home: rest position (3,) m of each foot (key: side index) before its first swing.
        clearance: swing apex above the higher of the two soles, m.
        dt: sample step, s (the swing rates are per second).
    """

    def __init__(self, home: dict[int, FloatArray], clearance: float, dt: float):
        self.clearance, self.dt = float(clearance), dt
        self.tracks = {foot: FootTrack(_pose(p)) for foot, p in home.items()}
        self._lift: dict[int, tuple[int, FloatArray]] = {}

    @property
    def home(self) -> dict[int, FloatArray]:
        """Rest position (3,) m of each foot: its last foothold touched down and not pruned."""
        return {foot: track.rest[:3] for foot, track in self.tracks.items()}

    def set_lift(self, foot: int, index: int, position: FloatArray) -> None:
        """The next swing of ``foot`` lifts off at sample ``index`` from ``position`` (3,)."""
        self._lift[foot] = (index, position)

    def swing_to(self, foot: int, touchdown: int, end: FloatArray) -> None:
        """Plan the next swing of ``foot``: from its lift-off (:meth:`set_lift`) to ``end`` (3,) at
        sample ``touchdown``."""
        i0, start = self._lift[foot]
        self.tracks[foot].swings.append(Swing(i0, touchdown, _pose(start), _pose(end), self.dt, self.clearance))

    def redirect(self, foot: int, now: int, touchdown: int, end: FloatArray) -> None:
        """Send the last planned swing of ``foot`` to ``end`` (3,) at ``touchdown``; a foot already in
        the air (lifted before sample ``now``) continues from its position, velocity and acceleration
        at ``now`` (:meth:`Swing.retarget`)."""
        self.tracks[foot].swings[-1].retarget(now, _pose(end), touchdown)

    def positions(self, foot: int, idx: IntArray) -> FloatArray:
        """Sole centre (len(idx), 3) of ``foot`` at the consecutive sample indices ``idx``."""
        return self.tracks[foot].positions(int(idx[0]), int(idx[-1]) + 1)[:, :3]

    def prune(self, upto: int) -> None:
        """Forget swings that touched down by sample ``upto`` (their end becomes the foot's rest)."""
        for track in self.tracks.values():
            track.prune(upto)
