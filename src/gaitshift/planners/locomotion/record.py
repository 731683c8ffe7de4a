"""A committed step: its type, where its phases fall on the sample grid, its points and headings.

Phase boundaries sit on samples: phase j of a step starting at sample ``i0`` covers
``[i0 + n_0 + ... + n_{j-1}, i0 + n_0 + ... + n_j)`` with ``n_j = round(duration_j / dt)`` (the
durations are multiples of dt). A sample at a boundary belongs to the phase that starts there.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from gaitshift.models.arrays import FloatArray
from gaitshift.planners.locomotion.sampling import Segment
from gaitshift.planners.locomotion.steps import Anchor, PhaseSpec, StepType

__all__ = ["StepRecord", "phase_samples"]


def phase_samples(step: StepType, dt: float) -> npt.NDArray[np.int64]:
    """Number of samples of each phase of ``step`` (phases are multiples of dt)."""
    return np.array([round(p.duration / dt) for p in step.phases], dtype=np.int64)


@dataclass
class StepRecord:
    """One step as committed on the sample grid.

    Attributes:
        step: its type.
        i0: first sample; ``bounds`` (len(phases)+1,) sample index of every phase boundary
            (``bounds[0] == i0``, ``bounds[-1]`` the next step's first sample).
        own, own_side: the stance foot (2,) and its side (for a start: the standing mid point and
            the side of the first stance foot).
        next, next_yaw, next_side: the foot that lands during this step (x, y), its yaw and side.
        knot, rest: the ZMP knot and rest point (2,) of a start or stop, else None.
        psi0, omega: heading at ``i0`` (rad) and the yaw rate during the step (rad/s).
        ground: height of the ground under the step, m.
        target: the target velocity (vx, vy) m/s and yaw rate rad/s the step was planned for.
    """

    step: StepType
    i0: int
    bounds: npt.NDArray[np.int64]
    own: FloatArray
    own_side: int
    next: FloatArray
    next_yaw: float
    next_side: int
    knot: FloatArray | None
    rest: FloatArray | None
    psi0: float
    omega: float
    ground: float
    target: FloatArray

    @property
    def i1(self) -> int:
        """First sample of the next step."""
        return int(self.bounds[-1])

    def phase_at(self, i: int) -> int:
        """Index of the phase that sample ``i`` belongs to."""
        return int(np.searchsorted(self.bounds, i, side="right") - 1)

    def point(self, a: Anchor) -> FloatArray:
        """The point an anchor names, (2,)."""
        p = {Anchor.OWN: self.own, Anchor.NEXT: self.next, Anchor.KNOT: self.knot, Anchor.REST: self.rest}[a]
        if p is None:
            raise ValueError(f"step {self.step.name} has no {a.name} point")
        return p

    def zmp_ends(self, ph: PhaseSpec) -> tuple[FloatArray, FloatArray] | tuple[None, None]:
        """ZMP (3,) at the start and end of a phase (ground height in z), or (None, None) in flight."""
        if ph.zmp is None:
            return None, None
        c0, c1 = self.point(ph.zmp.start), self.point(ph.zmp.end)
        return np.array([c0[0], c0[1], self.ground]), np.array([c1[0], c1[1], self.ground])

    def segments(self, i: int, p: FloatArray, v: FloatArray, dt: float) -> list[Segment]:
        """The segments from sample ``i`` (state p, v (3,) there) to the end of the step; the first one
        starts mid-phase when ``i`` is not a boundary. The state of later segments is filled in by
        the sampler (the last row of :func:`gaitshift.planners.locomotion.sampling.sample_segment`)."""
        out = []
        j0 = self.phase_at(i)
        for j in range(j0, len(self.step.phases)):
            ph = self.step.phases[j]
            a, b = int(self.bounds[j]), int(self.bounds[j + 1])
            start = i if j == j0 else a
            c0, c1 = self.zmp_ends(ph)
            if c0 is not None and c1 is not None and start > a:  # linear ZMP: its value at `start`
                frac = (start - a) / (b - a)
                c0 = c0 + (c1 - c0) * frac
            out.append(
                Segment(
                    ph.kind,
                    start,
                    b - start,
                    (b - start) * dt,
                    ph.stiffness,
                    p if j == j0 else np.array([np.nan, np.nan, ph.z0 + self.ground]),
                    v if j == j0 else np.array([np.nan, np.nan, ph.vz0]),
                    c0,
                    c1,
                )
            )
        return out
