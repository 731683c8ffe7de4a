"""Re-solving the rest of a TV-LIPM plan (paper 001) on new footholds, from a phase boundary.

A plan ``(seq, bp)`` is being executed; at boundary ``k`` (time ``t_k``) the footholds not yet
committed change (a map showed a tread higher than assumed, an edge under a planned sole). Phases
``k .. K-1`` keep their kind, duration and stiffness; their boundary states and ZMPs are solved again
under eq. (7)'s boxes of the new footholds, for all three axes, from boundary ``k``'s state:

.. math::

    p^+_k = p_k, \\qquad v^+_k = v_k, \\qquad c^+_k = c_k \\text{ (when phase } k \\text{ is a support)},
    \\qquad p^+_K = \\bar f_K + h\\, e_z, \\quad v^+_K = 0                                  (1)

with :math:`\\bar f_K` the mid-point of the closing soles and ``h`` the CoM height. The first two keep
the CoM's position and velocity continuous at ``t_k`` (eq. (1) of 001 then keeps the acceleration
continuous wherever the ZMP is); the third keeps the ZMP continuous when phase ``k`` is a support
(in a flight it does not act, and its box is the landing's, as in
:func:`gaitshift.planners.tvlip.boxes.boxes_from_flight`). The boxes are the whole new plan's, from
boundary ``k`` on. The vertical axis is solved again too: the
CoM rises or falls with the new footholds (the original planner solves z with the same hinge least
squares, :func:`gaitshift.planners.tvlip.planner.solve_boundaries`).

Boundaries ``0 .. k`` keep their old values, so the whole plan is one :class:`BoundaryPlan` and is
sampled by the usual closed forms.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from gaitshift.gait.footsteps import Footstep
from gaitshift.gait.sequence import GaitSequence
from gaitshift.planners.tvlip.boxes import Boxes, build_boxes
from gaitshift.planners.tvlip.kkt import BoundaryPlan, phase_coefficients, solve_axes
from gaitshift.trajectory.contract import FLIGHT, LEFT, RIGHT

__all__ = ["lift_phase", "resolve_from"]


def lift_phase(seq: GaitSequence) -> np.ndarray:
    """(M,) for each footstep the first phase of the swing that lands on it (its foot leaves its previous
    footstep at the start of that phase); -1 for the two initial footsteps. A footstep is *committed* at
    boundary ``k`` when its swing started before ``t_k``: ``lift_phase < k``."""
    on = seq.on  # (K, 2)
    m = len(seq.footsteps)
    out = np.full(m, -1, dtype=np.int64)
    for side in (LEFT, RIGHT):
        idx = np.flatnonzero(on[:, side] >= 0)  # the phases this foot stands in
        steps = on[idx, side]
        last = np.full(m, -1, dtype=np.int64)  # the last phase each footstep is stood on
        np.maximum.at(last, steps, idx)
        mine = np.unique(steps)  # this foot's footsteps, in order
        out[mine[1:]] = last[mine[:-1]] + 1  # the phase after the last one on the previous footstep
    return out


def resolve_from(
    seq: GaitSequence,
    bp: BoundaryPlan,
    k: int,
    footsteps: Sequence[Footstep],
    height: float,
    g: float,
    foot_size: Sequence[float],
    margin: float,
    zmp_z: Sequence[float] = (0.0, 0.0),
) -> tuple[GaitSequence, BoundaryPlan]:
    """The plan ``(seq, bp)`` with phases ``k ..`` re-solved on ``footsteps`` (module docstring, eq. (1)).

    ``footsteps`` has the same count and sides as ``seq.footsteps``; the committed ones (those whose
    :func:`lift_phase` is below ``k``) must be unchanged, which the caller guarantees. Returns the new
    sequence and the whole plan's :class:`BoundaryPlan` (rows ``0 .. k`` the old ones); its
    ``violation`` is the re-solved part's largest eq.-(7) violation (m), at ``violation_at`` (a whole-plan
    boundary index).
    """
    new = GaitSequence(seq.phases, tuple(footsteps), seq.step_gait)
    sub = GaitSequence(seq.phases[k:], tuple(footsteps), seq.step_gait)
    flight = seq.kind[k] == FLIGHT
    # the whole plan's boxes from boundary k (boundary k's box is the one of the phases on its two sides);
    # before a flight, the landing's box (its ZMP does not act)
    xy, z = (_from(b, k + 1 if flight else k, k) for b in build_boxes(new, foot_size, margin, zmp_z))
    fs, on = new.footstep_array, new.on
    goal = (fs[on[-1, LEFT], :3] + fs[on[-1, RIGHT], :3]) / 2
    goal[2] += height
    coef = phase_coefficients(sub.kind, sub.stiffness, sub.duration, g)
    zero2, zero1 = np.zeros(2), np.zeros(1)
    c_xy, c_z = (None, None) if flight else (bp.c[k, :2], bp.c[k, 2:])
    h = solve_axes(
        sub.kind, sub.stiffness, sub.duration, g, xy, bp.p[k, :2], bp.v[k, :2], goal[:2], zero2, 0.0,
        c_start=c_xy, coefficients=coef,
    )  # fmt: skip
    v = solve_axes(
        sub.kind, sub.stiffness, sub.duration, g, z, bp.p[k, 2:], bp.v[k, 2:], goal[2:], zero1, 1.0,
        c_start=c_z, coefficients=coef,
    )  # fmt: skip
    worst = h if h.violation >= v.violation else v
    rest = np.hstack([h.p, v.p]), np.hstack([h.v, v.v]), np.hstack([h.c, v.c])
    p, vel, c = (np.vstack([old[:k], r]) for old, r in zip((bp.p, bp.v, bp.c), rest, strict=True))
    if flight:  # boundary k's ZMP does not act in the flight after it: keep the old one (the past's)
        c[k] = bp.c[k]
    it = max(h.iterations, v.iterations)
    return new, BoundaryPlan(p, vel, c, it, worst.violation, k + worst.violation_at)


def _from(b: Boxes, first: int, k: int) -> Boxes:
    """Boxes of boundaries ``k ..`` with boundary ``k``'s box taken from boundary ``first``."""
    rows = np.r_[first, np.arange(k + 1, len(b.lo))]
    return Boxes(b.origin[rows], b.rot[rows], b.lo[rows], b.hi[rows])
