"""Closed-form sampling of planned phases: CoM position, velocity, acceleration and the ZMP.

In support, eq. (1) of paper 001 with constant T and a ZMP moving linearly from c0 to c1 has the
closed form of eqs. (3)-(4) (:func:`gaitshift.models.tvlip.support_state`); in flight the CoM is
ballistic (eqs. (5)-(6), sign of g corrected). Every sample is evaluated from its segment's start
state, so the dynamics hold at every sample to rounding and the CoM is C1 across segments (the end
state of one segment is the start state of the next).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from gaitshift.models.arrays import FloatArray
from gaitshift.trajectory.contract import FLIGHT

__all__ = ["Segment", "sample_segment", "segment_end"]


@dataclass(frozen=True)
class Segment:
    """A piece of one phase starting at sample ``i0`` with ``n`` samples; ``duration`` (s) is the
    time to the phase's end (``n dt`` up to rounding). ``p0``, ``v0`` (3,) the CoM state at ``i0``;
    ``c0``, ``c1`` (3,) the ZMP at ``i0`` and at the phase end (None in flight); T the stiffness."""

    kind: int
    i0: int
    n: int
    duration: float
    stiffness: float
    p0: FloatArray
    v0: FloatArray
    c0: FloatArray | None
    c1: FloatArray | None


def sample_segment(seg: Segment, dt: float, g: float) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """(pos, vel, acc, zmp), each (n + 1, 3), at samples ``i0 .. i0+n``: the last row is the state at
    the segment's end (the next segment's start). The ZMP is NaN in flight.

    Support, eqs. (3)-(4) of paper 001 with ``e0 = p0 - c0 - g T^2 e_z``, ``ed = v0 - cd``,
    ``cd = (c1 - c0)/tau`` and ``E = exp(s/T)`` (one exponential per sample)::

        p = c0 + cd s + g T^2 e_z + e0 cosh(s/T) + T ed sinh(s/T)
        v = cd + e0/T sinh(s/T) + ed cosh(s/T),   a = e0/T^2 cosh(s/T) + ed/T sinh(s/T)

    Flight, eqs. (5)-(6): ``p = p0 + v0 s - g s^2/2 e_z``."""
    s = np.arange(seg.n + 1, dtype=np.float64) * dt
    s[-1] = seg.duration
    ez = np.array([0.0, 0.0, 1.0])
    if seg.kind == FLIGHT or seg.c0 is None or seg.c1 is None:
        p = seg.p0 + np.outer(s, seg.v0) - np.outer(0.5 * g * s * s, ez)
        v = seg.v0 - np.outer(g * s, ez)
        a = np.tile(-g * ez, (len(s), 1))
        return p, v, a, np.full((len(s), 3), np.nan)
    T = seg.stiffness
    cd = (seg.c1 - seg.c0) / seg.duration
    e0 = seg.p0 - seg.c0 - g * T * T * ez
    ed = seg.v0 - cd
    E = np.exp(s / T)
    Ei = 1.0 / E
    ch, sh = 0.5 * (E + Ei), 0.5 * (E - Ei)
    zmp = seg.c0 + np.outer(s, cd)
    p = zmp + g * T * T * ez + np.outer(ch, e0) + np.outer(sh, T * ed)
    v = cd + np.outer(sh, e0 / T) + np.outer(ch, ed)
    a = np.outer(ch, e0 / (T * T)) + np.outer(sh, ed / T)
    return p, v, a, zmp


def segment_end(seg: Segment, dt: float, g: float) -> tuple[FloatArray, FloatArray]:
    """The CoM position and velocity (3,) each at the segment's end (the last row of
    :func:`sample_segment`, evaluated alone)."""
    p, v, _, _ = sample_segment(replace(seg, n=0), dt, g)
    return p[0], v[0]
