"""The planner's input (:class:`~.planner.Instant`) at the two kinds of planning instant: the start of
a step, and a re-plan from a measured CoM state within a step."""

from __future__ import annotations

from gaitshift.models.arrays import FloatArray
from gaitshift.planners.locomotion.planner import Instant, has_knot, is_start, touchdown_offset
from gaitshift.planners.locomotion.record import StepRecord
from gaitshift.planners.locomotion.steps import StepType

__all__ = ["within_step", "within_step_unknowns"]


def within_step_unknowns(rec: StepRecord, i: int, dt: float) -> tuple[FloatArray | None, int]:
    """At sample ``i`` of the step ``rec``: the next foot if it is already on the ground (a start, or
    after its touchdown), else None; and the number of unknowns of this step that come before the
    horizon's later steps (its knot, and its next foot while that is still in the air)."""
    land = rec.i0 + round(touchdown_offset(rec.step) / dt)
    next_fixed = rec.next if (is_start(rec.step) or i >= land) else None
    before = int(has_knot(rec.step)) + int(next_fixed is None and rec.step.name != "stop")
    return next_fixed, before


def within_step(
    rec: StepRecord,
    i: int,
    dt: float,
    types: tuple[StepType, ...],
    pos: FloatArray,
    vel: FloatArray,
    own_yaw: float,
    heading: float,
    next_fixed: FloatArray | None,
) -> Instant:
    """The instant of a re-plan at sample ``i`` of the step ``rec`` from the measured horizontal CoM
    position and velocity (2,) each; ``types`` the horizon, ``own_yaw`` the stance foot's yaw,
    ``heading`` the planned heading at ``i`` (rad); the target is the step's own."""
    j = rec.phase_at(i)
    return Instant(
        types,
        j,
        (i - int(rec.bounds[j])) * dt,
        (i - rec.i0) * dt,
        pos,
        vel,
        rec.own,
        own_yaw,
        rec.own_side,
        next_fixed,
        rec.next_yaw,
        heading,
        rec.omega,
        rec.target[:2].copy(),
    )
