"""Swing-foot tracks of a streaming generator: where each sole is at any planned sample index.

Each foot rests at its last foothold ("home") until it lifts off; a swing from sample ``i0`` (lift-off)
to ``i1`` (touchdown) follows :func:`gaitshift.gait.swing.swing_path`: a minimum-jerk horizontal
blend and the height sextic through the apex ``clearance`` above the higher sole. That path is linear
in (start, end, apex), so its basis is computed once per swing length and reused. Swings that ended
before the next emitted sample are forgotten (:meth:`FootTracks.prune`), so the tracks stay bounded.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from gaitshift.gait.swing import min_jerk, sextic_height_coefficients
from gaitshift.models.arrays import FloatArray, IntArray

__all__ = ["FootTracks", "SwingPath"]


@dataclass(frozen=True, eq=False)
class SwingPath:
    """A swing from sample ``i0`` (lift-off) to ``i1`` (touchdown) between the soles ``start`` and
    ``end`` (3,) m; ``path`` (i1 - i0, 3) holds the positions at samples i0..i1-1."""

    i0: int
    i1: int
    start: FloatArray
    end: FloatArray
    path: FloatArray


class FootTracks:
    """The planned swings of both feet and the foot positions they give.

    Args:
        home: rest position (3,) m of each foot (key: side index) before its first swing.
        clearance: swing apex above the higher of the two soles, m.
    """

    def __init__(self, home: dict[int, FloatArray], clearance: float):
        self.home = home
        self.clearance = clearance
        self.swings: dict[int, list[SwingPath]] = {foot: [] for foot in home}
        self._lift: dict[int, tuple[int, FloatArray]] = {}
        self._basis: dict[int, tuple[FloatArray, FloatArray]] = {}

    def path(self, i0: int, i1: int, start: FloatArray, end: FloatArray) -> SwingPath:
        """The swing from ``start`` at sample i0 to ``end`` at sample i1, its path sampled once."""
        n = i1 - i0
        basis = self._basis.get(n)
        if basis is None:
            u = np.arange(n) / max(n, 1)
            eye = np.eye(3)
            s_blend = min_jerk(u)  # horizontal blend
            coef = sextic_height_coefficients(eye[:, 0], eye[:, 1], eye[:, 2])  # (z0, z1, apex) -> (3, 7)
            zb = (u[:, None] ** np.arange(7)) @ coef.T  # (n, 3)
            basis = self._basis[n] = (s_blend, zb)
        s_blend, zb = basis
        path = start + (end - start) * s_blend[:, None]
        apex = max(start[2], end[2]) + float(self.clearance)
        path[:, 2] = zb @ np.array([start[2], end[2], apex])
        return SwingPath(i0, i1, start, end, path)

    def set_lift(self, foot: int, index: int, position: FloatArray) -> None:
        """The next swing of ``foot`` lifts off at sample ``index`` from ``position`` (3,)."""
        self._lift[foot] = (index, position)

    def swing_to(self, foot: int, touchdown: int, end: FloatArray) -> None:
        """Plan the next swing of ``foot``: from its lift-off (:meth:`set_lift`) to ``end`` (3,) at
        sample ``touchdown``."""
        i0, start = self._lift[foot]
        self.swings[foot].append(self.path(i0, touchdown, start, end))

    def redirect(self, foot: int, now: int, touchdown: int, end: FloatArray) -> None:
        """Send the last planned swing of ``foot`` to ``end`` at ``touchdown``; a foot already in the
        air (lifted before sample ``now``) continues from where it is at ``now``."""
        last = self.swings[foot][-1]
        i0, start = last.i0, last.start
        if now > i0:  # re-anchor the swing at the current foot position
            start = self.positions(foot, np.array([now]))[0]
            i0 = now
        self.swings[foot][-1] = self.path(i0, touchdown, start, end)

    def positions(self, foot: int, idx: IntArray) -> FloatArray:
        """Sole centre (len(idx), 3) of ``foot`` at the consecutive sample indices ``idx``."""
        pos = np.empty((len(idx), 3))
        pos[:] = self.home[foot]
        a, b = int(idx[0]), int(idx[-1]) + 1
        for sw in self.swings[foot]:
            if sw.i1 < b:  # touched down: stays at the foothold
                pos[max(sw.i1 - a, 0) :] = sw.end
            lo, hi = max(sw.i0, a), min(sw.i1, b)
            if lo < hi:
                pos[lo - a : hi - a] = sw.path[lo - sw.i0 : hi - sw.i0]
        return pos

    def prune(self, upto: int) -> None:
        """Forget swings that ended before sample ``upto`` (their end becomes the foot's rest)."""
        for foot, swings in self.swings.items():
            while swings and swings[0].i1 < upto:
                self.home[foot] = swings.pop(0).end
