"""Swing feet that can be re-targeted mid-swing, with analytic velocity and acceleration.

The one swing-foot tracker of the streaming generators (locomotion and VHIP). Horizontal position and
yaw follow a quintic in normalised time ``u`` from a start state ``(q0, q0', q0'')`` to the target
``(q1, 0, 0)``::

    q(u) = q0 + V u + A/2 u^2 + (10 D - 6 V - 3/2 A) u^3 + (-15 D + 8 V + 3/2 A) u^4 + (6 D - 3 V - 1/2 A) u^5

with ``D = q1 - q0``, ``V = q0' L``, ``A = q0'' L^2`` and L the remaining duration. From rest it is
the minimum-jerk blend of :mod:`gaitshift.gait.swing`. A re-target at sample i starts a new quintic
from the current state, so the foot reference stays C2 (no kink where a swing is redirected).

The height follows the sextic of paper 003 (:func:`gaitshift.gait.swing.sextic_height_coefficients`):
zero velocity and acceleration at lift-off and touchdown, apex ``clearance`` above the higher end at
mid-swing. A re-target keeps that sextic while the touchdown sample and height stay. When either
moves, the height restarts at sample i from its current state ``(z_i, z_i', z_i'')`` over the new
remaining duration L (:func:`height_from_state`)::

    z(u) = q(u) + (h - q(u_m)) [u (1 - u)]^3 / [u_m (1 - u_m)]^3

where q is the quintic above from ``(z_i, z_i', z_i'')`` to ``(z_1, 0, 0)``, h the apex height and
``u_m`` the new mid-swing time (half-way between lift-off and the new touchdown) in the new u. The
bump ``[u (1 - u)]^3`` has zero value, slope and curvature at u = 0 and u = 1, so z keeps the six
end conditions of q and passes through the apex at u_m: position, velocity and acceleration stay
continuous at the re-target. Past the mid-swing time (u_m <= 0) the apex is behind and z = q. From
rest at lift-off (u_m = 1/2) this is the sextic of paper 003 again.

:class:`FootTrack` holds one foot's rest pose and swings: :meth:`FootTrack.evaluate` gives poses, rates
and accelerations (the locomotion generator's foot columns), :meth:`FootTrack.positions` the poses
alone from a table sampled once per swing and re-target (the VHIP generator's per-tick feet).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field

import numpy as np

from gaitshift.gait.swing import sextic_height_coefficients
from gaitshift.models.arrays import FloatArray

__all__ = ["FootTrack", "Swing", "height_from_state", "quintic_from_state"]


def quintic_from_state(q0: FloatArray, v0: FloatArray, a0: FloatArray, q1: FloatArray, L: float) -> FloatArray:
    """Coefficients (6, k) in u of the quintic from (q0, v0, a0) (per second) to (q1, 0, 0) over L s."""
    D, V, A = q1 - q0, v0 * L, a0 * L * L
    return np.array([q0, V, 0.5 * A, 10 * D - 6 * V - 1.5 * A, -15 * D + 8 * V + 1.5 * A, 6 * D - 3 * V - 0.5 * A])


#: coefficients of the bump [u (1 - u)]^3 = u^3 - 3 u^4 + 3 u^5 - u^6
BUMP = np.array([0.0, 0.0, 0.0, 1.0, -3.0, 3.0, -1.0])


def height_from_state(z0: float, v0: float, a0: float, z1: float, L: float, apex: float, u_m: float) -> FloatArray:
    """Coefficients (7,) in u of the height from (z0, v0, a0) (per second) to (z1, 0, 0) over L s,
    through ``apex`` at ``u_m`` when 0 < u_m < 1 (module docstring: quintic plus the bump)."""
    q = np.zeros(7)
    q[:6] = quintic_from_state(np.array(z0), np.array(v0), np.array(a0), np.array(z1), L)
    if not 0.0 < u_m < 1.0:
        return q
    at = float(np.polynomial.polynomial.polyval(u_m, q))
    return q + (apex - at) / (u_m * (1.0 - u_m)) ** 3 * BUMP


def _powers(u: FloatArray, degree: int) -> FloatArray:
    """Rows [1, u, ..., u^degree] (n, degree + 1) by repeated products (cheaper than ``np.vander``)."""
    out = np.empty((len(u), degree + 1))
    out[:, 0] = 1.0
    out[:, 1] = u
    for k in range(2, degree + 1):
        np.multiply(out[:, k - 1], u, out=out[:, k])
    return out


#: columns of the stacked quintic (x, y, yaw; rates; accelerations) and of the sextic (z, z', z'') in
#: the (n, 12) output, ordered (x, y, z, yaw) x (pose, rate, acceleration)
_H_COLS = np.array([0, 1, 3, 4, 5, 7, 8, 9, 11])
_Z_COLS = np.array([2, 6, 10])


def _stacked(coef: FloatArray, L: float) -> FloatArray:
    """(d+1, 3k) matrix whose product with the Vandermonde rows [1, u, ..., u^d] gives the values, the
    time derivatives (1/L d/du) and the second time derivatives (1/L^2 d2/du2) of the polynomials
    ``coef`` (d+1, k) in normalised time u = t / L, side by side."""
    d = len(coef) - 1
    k = np.arange(1, d + 1, dtype=np.float64)
    d1 = np.zeros_like(coef)
    d2 = np.zeros_like(coef)
    d1[:d] = coef[1:] * k[:, None] / L
    d2[: d - 1] = coef[2:] * (k[1:] * k[:-1])[:, None] / L**2
    return np.hstack([coef, d1, d2])


@dataclass
class Swing:
    """One swing from sample ``i_lift`` (first sample off the ground) to ``i_land`` (first sample on
    the target). ``start`` and ``end`` are (x, y, z, yaw); times in samples of ``dt`` s. The current
    horizontal quintic ``coef`` starts at sample ``i_ref``, the height polynomial ``zcoef`` at
    ``i_zref`` (both ``i_lift`` until a re-target moves them)."""

    i_lift: int
    i_land: int
    start: FloatArray
    end: FloatArray
    dt: float
    clearance: float
    i_ref: int = 0
    i_zref: int = 0
    coef: FloatArray = field(default_factory=lambda: np.zeros((6, 3)))
    zcoef: FloatArray = field(default_factory=lambda: np.zeros(7))
    _key: tuple[int, int, int] = (-1, -1, -1)
    _hs: FloatArray = field(default_factory=lambda: np.zeros((6, 12)))
    _zs: FloatArray = field(default_factory=lambda: np.zeros((7, 12)))
    _table: FloatArray | None = None

    def __post_init__(self) -> None:
        self.i_ref = self.i_zref = self.i_lift
        L = (self.i_land - self.i_lift) * self.dt
        zero = np.zeros(3)
        self.coef = quintic_from_state(self.start[[0, 1, 3]], zero, zero, self.end[[0, 1, 3]], L)
        self.zcoef = sextic_height_coefficients(np.array(self.start[2]), np.array(self.end[2]), np.array(self.apex))

    @property
    def apex(self) -> float:
        """Apex height, m: ``clearance`` above the higher of lift-off and touchdown."""
        return float(max(self.start[2], self.end[2]) + self.clearance)

    def retarget(self, i: int, end: FloatArray, i_land: int | None = None) -> None:
        """Aim at ``end`` (x, y, z, yaw) from sample ``i`` on, touching down at ``i_land`` (default:
        the same sample), keeping position, velocity and acceleration at ``i``. The height keeps its
        sextic unless the touchdown sample or height moves (module docstring)."""
        if i >= self.i_land:
            return
        i = max(i, self.i_lift)
        land = self.i_land if i_land is None else int(i_land)
        p, v, a = self.evaluate(np.array([i]))
        moved = land != self.i_land or end[2] != self.end[2]
        L = (land - i) * self.dt
        self.coef = quintic_from_state(p[0, [0, 1, 3]], v[0, [0, 1, 3]], a[0, [0, 1, 3]], end[[0, 1, 3]], L)
        self.i_ref, self.i_land = i, land
        self._key, self._table = (-1, -1, -1), None
        self.end = np.array(end, dtype=np.float64)
        if not moved:
            return
        self.i_zref = i
        if i == self.i_lift:  # still on the ground: the sextic of paper 003 to the new touchdown
            self.zcoef = sextic_height_coefficients(np.array(self.start[2]), np.array(self.end[2]), np.array(self.apex))
        else:
            u_m = (0.5 * (self.i_lift + land) - i) / (land - i)
            self.zcoef = height_from_state(p[0, 2], v[0, 2], a[0, 2], self.end[2], L, self.apex, u_m)

    def _powers_at(self, idx: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Powers [1, u, ..., u^5] (n, 6) of the horizontal time and [1, u, ..., u^6] (n, 7) of the
        height time at sample indices ``idx`` (n,), each u clipped to [0, 1]."""
        Lh = (self.i_land - self.i_ref) * self.dt
        Lz = (self.i_land - self.i_zref) * self.dt
        uh = np.clip((idx - self.i_ref) * self.dt / Lh, 0.0, 1.0)
        uz = np.clip((idx - self.i_zref) * self.dt / Lz, 0.0, 1.0)
        pz = _powers(uz, 6)
        ph = pz[:, :6] if self.i_ref == self.i_zref else _powers(uh, 5)
        return ph, pz

    def evaluate(self, idx: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """(x, y, z, yaw), their rates and accelerations at sample indices ``idx`` (n,): (n, 4) each."""
        idx = np.asarray(idx, dtype=np.float64)
        if self._key != (self.i_ref, self.i_zref, self.i_land):  # the stacked coefficients of the current polynomials
            self._key = (self.i_ref, self.i_zref, self.i_land)
            self._hs, self._zs = np.zeros((6, 12)), np.zeros((7, 12))
            self._hs[:, _H_COLS] = _stacked(self.coef, (self.i_land - self.i_ref) * self.dt)
            self._zs[:, _Z_COLS] = _stacked(self.zcoef[:, None], (self.i_land - self.i_zref) * self.dt)
        ph, pz = self._powers_at(idx)
        out = (ph @ self._hs + pz @ self._zs).reshape(len(idx), 3, 4)
        pos, vel, acc = out[:, 0], out[:, 1], out[:, 2]
        done = idx >= self.i_land
        if done.any():
            pos[done], vel[done], acc[done] = self.end, 0.0, 0.0
        return pos, vel, acc

    def sampled(self, lo: int, hi: int) -> FloatArray:
        """Poses (hi - lo, 4) at the samples lo..hi-1 (within the swing), read from a table of the
        current polynomials sampled once per re-target (a sample before ``i_ref`` reads its first row,
        as :meth:`evaluate` clips)."""
        if self._table is None:  # positions only: the (n, 6) and (n, 7) products, no rates
            ph, pz = self._powers_at(np.arange(self.i_ref, self.i_land, dtype=np.float64))
            self._table = np.empty((len(pz), 4))
            self._table[:, [0, 1, 3]] = ph @ self.coef
            self._table[:, 2] = pz @ self.zcoef
        if lo >= self.i_ref:
            return self._table[lo - self.i_ref : hi - self.i_ref]
        return self._table[np.maximum(np.arange(lo, hi) - self.i_ref, 0)]


@dataclass
class FootTrack:
    """One foot over time: where it rests (x, y, z, yaw) and its swings (past ones pruned)."""

    rest: FloatArray
    swings: list[Swing] = field(default_factory=list)

    def active(self, i: int) -> Swing | None:
        """The swing in the air at sample ``i`` (lift-off <= i < touchdown), if any."""
        for sw in self.swings:
            if sw.i_lift <= i < sw.i_land:
                return sw
        return None

    def pending(self, i: int) -> Swing | None:
        """The swing that has not touched down by sample ``i`` (in the air or still to lift)."""
        for sw in self.swings:
            if i < sw.i_land:
                return sw
        return None

    def landed(self, i: int) -> FloatArray:
        """The resting pose (x, y, z, yaw) at sample ``i``: the end of the last swing touched down by
        then, or the rest pose (valid when no swing is in the air at ``i``)."""
        pose = self.rest
        for sw in self.swings:
            if sw.i_land > i:
                break
            pose = sw.end
        return pose

    def _segments(self, a: int, b: int) -> Iterator[tuple[Swing, int, int]]:
        """The swings over samples a..b-1, each with its samples ``lo..hi-1`` inside them (every swing
        lands before the next one lifts); the pose before the first is :attr:`rest`, after each its end."""
        for sw in self.swings:
            if sw.i_land <= a:
                yield sw, a, a  # landed before the window: its end holds from a on
                continue
            lo = max(sw.i_lift, a)
            if lo >= b:
                return
            yield sw, lo, min(sw.i_land, b)

    def evaluate(
        self, a: int, b: int, out: tuple[FloatArray, FloatArray, FloatArray] | None = None
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Pose (x, y, z, yaw), rates and accelerations at samples a..b-1: (b-a, 4) each (written into
        ``out`` if given)."""
        n = b - a
        pos, vel, acc = out if out is not None else (np.empty((n, 4)), np.empty((n, 4)), np.empty((n, 4)))
        pos[:] = self.rest
        vel[:] = 0.0
        acc[:] = 0.0
        for sw, lo, hi in self._segments(a, b):
            if lo < hi:
                p, v, ac = sw.evaluate(np.arange(lo, hi, dtype=np.float64))
                pos[lo - a : hi - a], vel[lo - a : hi - a], acc[lo - a : hi - a] = p, v, ac
            pos[hi - a :], vel[hi - a :], acc[hi - a :] = sw.end, 0.0, 0.0
        return pos, vel, acc

    def positions(self, a: int, b: int) -> FloatArray:
        """Pose (x, y, z, yaw) at samples a..b-1, (b-a, 4): the positions of :meth:`evaluate` (to rounding),
        each swing sampled once (:meth:`Swing.sampled`), for a caller that needs no rates (a cheap
        control tick: a slice per swing)."""
        pos = np.empty((b - a, 4))
        pos[:] = self.rest
        for sw, lo, hi in self._segments(a, b):
            if lo < hi:
                pos[lo - a : hi - a] = sw.sampled(lo, hi)
            pos[hi - a :] = sw.end
        return pos

    def prune(self, i: int) -> None:
        """Forget swings that touched down before sample ``i``; the last one's end is the rest."""
        while self.swings and self.swings[0].i_land <= i:
            self.rest = self.swings.pop(0).end
