"""Step types of the locomotion generator: the contact phases of one step, with their stiffness.

A *step* is the single support on one foot followed by the transfer to the next foot: a double
support (walking) or a flight (running). Every phase obeys eq. (1) of paper 001,
``p'' = (p - c)/T^2 - g e_z``, with a constant stiffness T and a ZMP ``c`` moving linearly in the
phase. The stiffness of each phase is chosen so that the vertical CoM state closes exactly at every
phase boundary (paper 001 §III, docs/locomotion.md "Step types"):

==============  ===============================  ================================  =========
step type       phases                           vertical state at the SS start    gait
==============  ===============================  ================================  =========
``walk``        SS(T_w), DS(T_w)                 (h, 0)                            walking
``walk_to_run`` SS(T_w), DS(T_t0)                (h, 0)                            walking
``run_start``   SS(T_t1), F                      (z_t, v_t) = DS(T_t0) map of (h,0) running
``run``         SS(T_r), F                       (h, v_r)                          running
``run_to_walk`` SS(T_t1), DS(T_t0)               (h, v_r)                          walking
``start``       DS(T_w) in two halves            (h, 0), at rest                   standing
``start_run``   ``start`` + DS(T_t0)             (h, 0), at rest                   standing
``stop``        SS(T_w), DS(T_w) in two halves   (h, 0)                            walking
==============  ===============================  ================================  =========

Walking SS lasts ``walk_single``, running and transition SS ``run_single`` (the SS of eqs. (12)-(14)
is the one that ends in the take-off). The ZMP of each phase is given symbolically
(:class:`ZmpEnds`): at the stance foot, moving to the next foot, or through a free knot (start/stop).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import IntEnum

from gaitshift.models.stiffness import Stiffness
from gaitshift.models.tvlip import support_map_1d
from gaitshift.trajectory.contract import DS, FLIGHT, SS

__all__ = [
    "GAIT_CODES",
    "STEP_CODES",
    "SUCCESSOR",
    "Anchor",
    "Gait",
    "PhaseSpec",
    "StepType",
    "Timing",
    "ZmpEnds",
    "build_step_types",
]


class Gait(IntEnum):
    """The ``gait`` key of the trajectory file."""

    STAND = 0
    WALK = 1
    RUN = 2


GAIT_CODES = {"stand": Gait.STAND, "walk": Gait.WALK, "run": Gait.RUN}
#: the ``step_type`` extra of a locomotion trajectory: step type name -> code (-1: standing)
STEP_CODES = {
    "start": 0,
    "start_run": 1,
    "walk": 2,
    "walk_to_run": 3,
    "run_start": 4,
    "run": 5,
    "run_to_walk": 6,
    "stop": 7,
}


class Anchor(IntEnum):
    """Where a ZMP end point of a phase sits: the step's own foot, the next foot, the step's free
    knot, or the rest point between the own and the next foot (``stop``)."""

    OWN = 0
    NEXT = 1
    KNOT = 2
    REST = 3


@dataclass(frozen=True)
class ZmpEnds:
    """ZMP at the start and the end of a phase (linear in between); ``None`` in flight."""

    start: Anchor
    end: Anchor


@dataclass(frozen=True)
class PhaseSpec:
    """One phase: kind (DS, SS, FLIGHT), duration (s), stiffness T (s, NaN in flight), the ZMP ends
    (None in flight), and the vertical CoM state at its start, (z, z') relative to the ground (m, m/s)."""

    kind: int
    duration: float
    stiffness: float
    zmp: ZmpEnds | None
    z0: float
    vz0: float


@dataclass(frozen=True)
class StepType:
    """A step type (see the module table): its phases, the gait it belongs to, and whether it can
    repeat (a periodic orbit exists: ``walk`` and ``run``)."""

    name: str
    gait: Gait
    phases: tuple[PhaseSpec, ...]
    steady: bool

    @property
    def duration(self) -> float:
        """Step duration, s."""
        return sum(p.duration for p in self.phases)

    @property
    def single_support(self) -> float:
        """Duration of the single support, s (0 for the start)."""
        return sum(p.duration for p in self.phases if p.kind == SS)


@dataclass(frozen=True)
class Timing:
    """Phase durations, s. Walking SS ``walk_single``; running and transition SS ``run_single``;
    double support ``double``; flight ``flight``; standing DS before the first step ``start`` and
    after the closing step ``stop``."""

    walk_single: float
    double: float
    run_single: float
    flight: float
    start: float
    stop: float


#: (current step type, desired gait) -> next step type. Transitions are forced: a walk-to-run step
#: is always followed by the running start; a run-to-walk step lands, so the next one walks.
SUCCESSOR: dict[tuple[str, Gait], str] = {
    ("walk", Gait.WALK): "walk",
    ("walk", Gait.RUN): "walk_to_run",
    ("walk_to_run", Gait.WALK): "run_start",
    ("walk_to_run", Gait.RUN): "run_start",
    ("run_start", Gait.WALK): "run_to_walk",
    ("run_start", Gait.RUN): "run",
    ("run", Gait.WALK): "run_to_walk",
    ("run", Gait.RUN): "run",
    ("run_to_walk", Gait.WALK): "walk",
    ("run_to_walk", Gait.RUN): "walk_to_run",
    ("start", Gait.WALK): "walk",
    ("start", Gait.RUN): "walk",
    ("start_run", Gait.WALK): "run_start",
    ("start_run", Gait.RUN): "run_start",
}


def _ph(kind: int, tau: float, T: float, zmp: ZmpEnds | None, z0: float, vz0: float) -> PhaseSpec:
    return PhaseSpec(kind, tau, T, zmp, z0, vz0)


def build_step_types(k: Stiffness, timing: Timing, height: float, gravity: float) -> dict[str, StepType]:
    """All step types for one robot and timing (see the module table).

    Args:
        k: stiffness values of paper 001 for ``(height, run_single, double, flight)``; ``T_w`` is
            sqrt(h/g) and so also serves the walking SS of any duration.
        timing: phase durations, s.
        height: nominal CoM height h above the ground, m.
        gravity: g, m/s^2.
    """
    h, tm = height, timing
    own, move, rest = ZmpEnds(Anchor.OWN, Anchor.OWN), ZmpEnds(Anchor.OWN, Anchor.NEXT), None
    # vertical state after DS(T_t0) from (h, 0): the running take-off preparation (eq. (12))
    zt, vt, _, _ = support_map_1d(h, 0.0, k.T_t0, tm.double, gravity)
    zt, vt = float(zt), float(vt)
    vr = k.v_r
    half = 0.5 * tm.start
    # the start: DS from the feet's middle to a free knot, then to the first stance foot
    start = (
        _ph(DS, half, k.T_w, ZmpEnds(Anchor.OWN, Anchor.KNOT), h, 0.0),
        _ph(DS, half, k.T_w, ZmpEnds(Anchor.KNOT, Anchor.NEXT), h, 0.0),
    )
    types = [
        StepType(
            "walk",
            Gait.WALK,
            (_ph(SS, tm.walk_single, k.T_w, own, h, 0.0), _ph(DS, tm.double, k.T_w, move, h, 0.0)),
            True,
        ),
        StepType(
            "walk_to_run",
            Gait.WALK,
            (_ph(SS, tm.walk_single, k.T_w, own, h, 0.0), _ph(DS, tm.double, k.T_t0, move, h, 0.0)),
            False,
        ),
        StepType(
            "run_start",
            Gait.RUN,
            (_ph(SS, tm.run_single, k.T_t1, own, zt, vt), _ph(FLIGHT, tm.flight, math.nan, rest, h, -vr)),
            False,
        ),
        StepType(
            "run",
            Gait.RUN,
            (_ph(SS, tm.run_single, k.T_r, own, h, vr), _ph(FLIGHT, tm.flight, math.nan, rest, h, -vr)),
            True,
        ),
        # time reverse of the take-off preparation: SS(T_t1) lands, DS(T_t0) ends at (h, 0)
        StepType(
            "run_to_walk",
            Gait.WALK,
            (_ph(SS, tm.run_single, k.T_t1, own, h, vr), _ph(DS, tm.double, k.T_t0, move, zt, -vt)),
            False,
        ),
        StepType("start", Gait.STAND, start, False),
        StepType(
            "start_run",
            Gait.STAND,
            (*start, _ph(DS, tm.double, k.T_t0, ZmpEnds(Anchor.NEXT, Anchor.NEXT), h, 0.0)),
            False,
        ),
        StepType(
            "stop",
            Gait.WALK,
            (
                _ph(SS, tm.walk_single, k.T_w, own, h, 0.0),
                _ph(DS, 0.5 * tm.stop, k.T_w, ZmpEnds(Anchor.OWN, Anchor.KNOT), h, 0.0),
                _ph(DS, 0.5 * tm.stop, k.T_w, ZmpEnds(Anchor.KNOT, Anchor.REST), h, 0.0),
            ),
            False,
        ),
    ]
    return {t.name: t for t in types}
