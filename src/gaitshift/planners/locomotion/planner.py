"""One planning instant: choose the next footholds (and the start/stop ZMP knots) from the CoM state.

The horizon is the current step followed by the steps the gait selection fixes (:func:`horizon`),
up to either the first steady step, whose SS start is the target (the periodic orbit of
:mod:`.orbit` at the target velocity and yaw rate, in the frame of that step's stance foot), or the
``stop`` step, whose end is the target (rest over the middle of the feet: ``x = rest point``,
``v = 0``). :mod:`.horizon` solves it. The unknowns are, per free foot, its displacement from the
previous foot in the frame of its own yaw, bounded by the kinematic limits (``|d_x| <= max_stride``,
lateral separation within ``width``), and per start/stop knot its offset inside the double-support
polygon (both soles shrunk by ``zmp_margin``), so every committed foothold is reachable and every
ZMP is inside its support polygon.

Headings: the yaw rate is constant over the horizon, ``psi(t) = psi_now + omega (t - t_now)``; a
foot's yaw is the heading at its touchdown; nominal displacements are ``[V_x tau, -/+ w + V_y tau]``
(tau the step duration, w the step width; the next foot is to the right of a left stance).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from gaitshift.common.rotations import rot2
from gaitshift.models.arrays import FloatArray, Int8Array
from gaitshift.planners.locomotion.affine import Affine
from gaitshift.planners.locomotion.horizon import HorizonStep, Row, Unknowns, rollout, solve
from gaitshift.planners.locomotion.orbit import Orbit
from gaitshift.planners.locomotion.params import LocomotionParams
from gaitshift.planners.locomotion.steps import SUCCESSOR, Anchor, Gait, StepType
from gaitshift.trajectory.contract import FLIGHT, LEFT, SS

__all__ = ["Instant", "Plan", "has_knot", "horizon", "is_start", "plan_instant", "touchdown_offset"]

#: weights of the minimum-norm objective (1/m^2): displacements and knots pulled to their nominal
W_FOOT = 1.0
W_KNOT = 1.0
#: weight of the convergent part of the target error in the bounded fallback (divergent part: 1)
W_CONVERGENT = 0.1


def is_start(step: StepType) -> bool:
    """True for the start step types (no single support; the next foot is already down)."""
    return step.name.startswith("start")


def has_knot(step: StepType) -> bool:
    """True if a phase of the step has a free ZMP knot (start and stop)."""
    return any(p.zmp is not None and Anchor.KNOT in (p.zmp.start, p.zmp.end) for p in step.phases)


def touchdown_offset(step: StepType) -> float:
    """Time from the step's start at which its next foot touches down, s: the end of the single
    support when a double support follows, the end of the flight when running, 0 for a start (its
    next foot, the first stance foot, is on the ground already)."""
    if is_start(step):
        return 0.0
    if step.phases[-1].kind == FLIGHT:
        return step.duration
    return step.single_support


def horizon(
    types: dict[str, StepType], current: str, first_next: str, gait: Gait, *, stopping: bool, unknowns_before: int
) -> tuple[StepType, ...]:
    """The step types from ``current`` (then ``first_next``) to the target step: the first steady
    step once at least two unknown points precede it, or the ``stop`` step.

    ``unknowns_before`` counts the unknown points ``current`` contributes (its next foot if still
    in the air, its knot)."""
    seq = [types[current], types[first_next]]
    count = unknowns_before
    while True:
        last = seq[-1]
        if last.name == "stop" or (last.steady and count >= 2 and not stopping):
            return tuple(seq)
        count += 1 + int(has_knot(last))
        walkable = last.gait != Gait.RUN and last.name != "walk_to_run"
        nxt = "stop" if stopping and walkable else SUCCESSOR[(last.name, Gait.WALK if stopping else gait)]
        seq.append(types[nxt])
        if len(seq) > 8:  # pragma: no cover - the successor table reaches a target in <= 4 steps
            raise RuntimeError(f"no target within 8 steps from {current}")


@dataclass(frozen=True)
class Instant:
    """The planner's input at one instant (world frame unless said).

    Attributes:
        types: the horizon's step types (:func:`horizon`); ``types[0]`` is the step under way.
        first_phase, elapsed: phase index of ``types[0]`` and time spent in it, s.
        time_in_step: time from the start of ``types[0]`` to now, s.
        x, v: CoM position and velocity now, (2,) each, m and m/s.
        own, own_yaw: the current step's own point (2,) and yaw: its stance foot (for a start: the
            middle of the standing feet and their mean yaw).
        own_side: side of the foot of the first single support in the horizon (LEFT/RIGHT).
        next_fixed: the next foot (2,) if it is on the ground already (a start, or a re-plan in double
            support), else None; ``next_yaw`` its yaw.
        heading, yaw_rate: heading now (rad) and the yaw rate over the horizon (rad/s).
        velocity: target velocity (2,) in the heading frame, m/s.
        goal: the rest point (2,) a ``stop`` must end on, or None (free); ``stop_yaw`` the closing
            feet's yaw (None: the heading at their touchdown).
    """

    types: tuple[StepType, ...]
    first_phase: int
    elapsed: float
    time_in_step: float
    x: FloatArray
    v: FloatArray
    own: FloatArray
    own_yaw: float
    own_side: int
    next_fixed: FloatArray | None
    next_yaw: float
    heading: float
    yaw_rate: float
    velocity: FloatArray
    goal: FloatArray | None = None
    stop_yaw: float | None = None


@dataclass(frozen=True)
class Plan:
    """The next foot of every step of the horizon (n, 2), its yaw (n,) and side (n,); the knots by
    step index; whether the target was met exactly; the horizon's step types."""

    footholds: FloatArray
    yaws: FloatArray
    sides: Int8Array
    knots: dict[int, FloatArray]
    exact: bool
    types: tuple[StepType, ...]


def _yaws_sides(inst: Instant) -> tuple[list[float], list[float], list[int]]:
    """Per step: start time (from the current step's start), the yaw of its next foot, the side of
    its own foot."""
    starts, yaws, sides = [], [], []
    t, side = 0.0, inst.own_side
    for j, st in enumerate(inst.types):
        starts.append(t)
        sides.append(side)
        if is_start(st) or (j == 0 and inst.next_fixed is not None):
            yaws.append(inst.next_yaw)
        elif inst.stop_yaw is not None and (
            st.name == "stop"
            or (inst.goal is not None and j + 1 < len(inst.types) and inst.types[j + 1].name == "stop")
        ):
            yaws.append(inst.stop_yaw)
        else:
            yaws.append(inst.heading + inst.yaw_rate * (t + touchdown_offset(st) - inst.time_in_step))
        side = side if is_start(st) else 1 - side
        t += st.duration
    return starts, yaws, sides


def _ds_box(params: LocomotionParams, separation: float) -> tuple[FloatArray, FloatArray]:
    """Bounds of a knot's offset from the middle of two side-by-side soles (their frame), m."""
    L, W = params.foot_size
    m = params.zmp_margin
    half = np.array([0.5 * L - m, 0.5 * separation + 0.5 * W - m])
    return -half, half


def _nominal_step(inst: Instant, st: StepType, side: int, w: float, orbits: dict[str, Orbit]) -> FloatArray:
    """Nominal displacement of a step from a stance on ``side`` (landing frame): the steady pattern
    of its gait at the target velocity and yaw rate (:meth:`Orbit.pattern`)."""
    steady = "run" if st.gait == Gait.RUN else "walk"
    dL, dR = orbits[steady].pattern(inst.velocity, w, inst.yaw_rate)
    return dL if side == LEFT else dR


def _build(
    inst: Instant, params: LocomotionParams, orbits: dict[str, Orbit]
) -> tuple[list[HorizonStep], Unknowns, list[float], list[int]]:
    """Horizon steps with affine points, and their unknowns (module docstring)."""
    lim, w = params.limits, params.step_width
    _starts, yaws, sides = _yaws_sides(inst)
    n_roll = len(inst.types) - 1 if inst.types[-1].steady else len(inst.types)
    unk = Unknowns()
    slots: list[tuple[str, int, int]] = []  # (kind, step, index of the first unknown)
    for j in range(n_roll):
        st, sign = inst.types[j], (-1.0 if sides[j] == LEFT else 1.0)
        if has_knot(st):
            sep = (
                w
                if st.name == "stop"
                else float(np.linalg.norm(inst.next_fixed - inst.own)) * 2.0
                if inst.next_fixed is not None
                else w
            )
            lo, hi = _ds_box(params, sep)
            slots.append(("knot", j, unk.add_pair(np.zeros(2), W_KNOT, lo, hi)))
        fixed = is_start(st) or st.name == "stop" or (j == 0 and inst.next_fixed is not None)
        goal_fixed = inst.goal is not None and j + 1 < len(inst.types) and inst.types[j + 1].name == "stop"
        if not (fixed or goal_fixed):
            nominal = _nominal_step(inst, st, sides[j], w, orbits)
            lat = sorted((sign * lim.width[0], sign * lim.width[1]))
            slots.append(
                ("foot", j, unk.add_pair(nominal, W_FOOT, [-lim.max_stride, lat[0]], [lim.max_stride, lat[1]]))
            )
    n = unk.n
    index = {(k, j): i for k, j, i in slots}
    own = Affine.constant(inst.own, n)
    steps: list[HorizonStep] = []
    for j, st in enumerate(inst.types):
        R = rot2(yaws[j])
        sign = -1.0 if sides[j] == LEFT else 1.0
        knot = rest = None
        if ("foot", j) in index:
            nxt = own + Affine.unknowns(index[("foot", j)], n, R)
        elif st.name == "stop":
            nxt = own.shift(R @ np.array([0.0, sign * w]))
            rest = own.shift(R @ np.array([0.0, 0.5 * sign * w]))
        elif (j == 0 or is_start(st)) and inst.next_fixed is not None:
            nxt = Affine.constant(inst.next_fixed, n)
        elif inst.goal is not None and j + 1 < len(inst.types) and inst.types[j + 1].name == "stop":
            side = -1.0 if sides[j + 1] == LEFT else 1.0
            nxt = Affine.constant(inst.goal - rot2(yaws[j + 1]) @ np.array([0.0, 0.5 * side * w]), n)
        else:  # the target step's own foot lies beyond the rollout: never used as an anchor
            nxt = own
        if ("knot", j) in index:
            centre = rest if rest is not None else own
            knot = centre + Affine.unknowns(index[("knot", j)], n, rot2(yaws[j] if rest is not None else inst.own_yaw))
        first = j == 0
        steps.append(
            HorizonStep(st, own, nxt, knot, rest, inst.first_phase if first else 0, inst.elapsed if first else 0.0)
        )
        own = nxt
    return steps, unk, yaws, sides


def _rows(
    inst: Instant,
    steps: list[HorizonStep],
    yaws: list[float],
    sides: list[int],
    orbits: dict[str, Orbit],
    params: LocomotionParams,
) -> list[Row]:
    """The target conditions as divergent/convergent combinations ``e +/- T_c e'``."""
    n = steps[0].own.J.shape[1]
    target = inst.types[-1]
    T_c = (
        next(p.stiffness for p in target.phases if p.kind == SS)
        if target.steady
        else next(p.stiffness for p in target.phases if p.kind != FLIGHT)
    )
    if target.steady:
        ends = rollout(steps[:-1], Affine.constant(inst.x, n), Affine.constant(inst.v, n))
        x, v = ends[-1]
        j = len(inst.types) - 1
        yaw = yaws[j - 1]  # the target stance foot is the previous step's next foot
        rho, nu = orbits[target.name].state(inst.velocity, params.step_width, sides[j], inst.yaw_rate)
        R = rot2(yaw)
        e, e_target, ed_target = x - steps[j].own, R @ rho, R @ nu
    else:
        ends = rollout(steps, Affine.constant(inst.x, n), Affine.constant(inst.v, n))
        x, v = ends[-1]
        rest = steps[-1].rest
        assert rest is not None
        e, e_target, ed_target = x - rest, np.zeros(2), np.zeros(2)
    return [
        Row(e + v.scale(T_c), e_target + T_c * ed_target, 1.0),
        Row(e - v.scale(T_c), e_target - T_c * ed_target, W_CONVERGENT),
    ]


#: how many steady steps a horizon may be extended by when the limits forbid a shorter deadbeat
MAX_EXTRA_STEPS = 4


def plan_instant(inst: Instant, params: LocomotionParams, orbits: dict[str, Orbit]) -> Plan:
    """Solve the foothold problem of one instant (module docstring). When the limits forbid reaching
    the target in the given horizon, the target moves one steady step further (up to
    :data:`MAX_EXTRA_STEPS`): the fewest steps the limits allow, the correction spread over them;
    only if none is exact does the bounded least-squares compromise of the longest horizon stand."""
    for extra in range(MAX_EXTRA_STEPS + 1 if inst.types[-1].steady else 1):
        trial = replace(inst, types=inst.types + (inst.types[-1],) * extra)
        plan = _solve_instant(trial, params, orbits)
        if plan.exact:
            return plan
    return plan


def _solve_instant(inst: Instant, params: LocomotionParams, orbits: dict[str, Orbit]) -> Plan:
    steps, unk, yaws, sides = _build(inst, params, orbits)
    sol = solve(_rows(inst, steps, yaws, sides, orbits, params), unk)
    n_roll = len(inst.types) - 1 if inst.types[-1].steady else len(inst.types)
    feet = np.array([hs.next.value(sol.u) for hs in steps[:n_roll]]).reshape(-1, 2)
    knots = {j: hs.knot.value(sol.u) for j, hs in enumerate(steps[:n_roll]) if hs.knot is not None}
    next_sides = np.array([sides[j] if is_start(inst.types[j]) else 1 - sides[j] for j in range(n_roll)], dtype=np.int8)
    return Plan(feet, np.array(yaws[:n_roll]), next_sides, knots, sol.exact, inst.types)
