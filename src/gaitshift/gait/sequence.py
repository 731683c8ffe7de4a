"""Gait sequences: contact phases (DS, SS, F) with durations and stiffness, and footsteps.

A plan starts and ends standing on both feet at rest. Footstep indices 0 and 1 are the initial left
and right feet; each step adds one foothold; a closing step places the trailing foot beside the last
one. Phase layout (paper 001, Fig. 2)::

    DS_start, [DS_t0 if step 1 runs], then per step: SS + (DS if walk else F),
    closing step: SS + DS, DS_stop

The stiffness of each support phase follows from its neighbours so that the vertical CoM motion
closes exactly (see :mod:`gaitshift.models.stiffness`):

=====================  ==========================  ========
phase                  neighbours                  T
=====================  ==========================  ========
SS                     DS before, DS after         T_w
SS                     F before, F after           T_r
SS                     DS/F or F/DS                T_t1
DS                     before a DS->SS->F take-off T_t0
DS                     after an F->SS->DS landing  T_t0
DS                     otherwise                   T_w
F                      -                           NaN
=====================  ==========================  ========
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from gaitshift.errors import InputError
from gaitshift.gait.footsteps import Footstep
from gaitshift.models.arrays import FloatArray, Int8Array, IntArray
from gaitshift.models.stiffness import Stiffness
from gaitshift.trajectory.contract import DS, FLIGHT, SS


@dataclass(frozen=True)
class Phase:
    """A contact phase: kind (DS=0, SS=1, F=2), duration (s), stiffness T (s; NaN in flight) and the
    footstep index each foot stands on (left, right), -1 while that foot swings."""

    kind: int
    duration: float
    stiffness: float
    on: tuple[int, int]


@dataclass(frozen=True)
class GaitSequence:
    """Phases and footsteps of a whole plan.

    Attributes:
        phases: the K contact phases in order.
        footsteps: the M footholds; 0 and 1 are the initial left and right feet.
        step_gait: "walk" or "run" for each commanded step (closing step excluded).
    """

    phases: tuple[Phase, ...]
    footsteps: tuple[Footstep, ...]
    step_gait: tuple[str, ...]

    @cached_property
    def _arrays(self) -> dict[str, np.ndarray]:
        """The per-phase and per-footstep arrays, built once (the properties hand out copies)."""
        duration = np.array([p.duration for p in self.phases])
        return {
            "kind": np.array([p.kind for p in self.phases], dtype=np.int8),
            "duration": duration,
            "stiffness": np.array([p.stiffness for p in self.phases]),
            "on": np.array([p.on for p in self.phases], dtype=int),
            "boundary_times": np.concatenate([[0.0], np.cumsum(duration)]),
            "footstep_array": np.array([[f.x, f.y, f.z, f.yaw] for f in self.footsteps], dtype=float).reshape(-1, 4),
            "footstep_side": np.array([f.side for f in self.footsteps], dtype=np.int8),
        }

    @property
    def kind(self) -> Int8Array:
        """(K,) int8 phase kinds."""
        return self._arrays["kind"].copy()

    @property
    def duration(self) -> FloatArray:
        """(K,) phase durations, s."""
        return self._arrays["duration"].copy()

    @property
    def stiffness(self) -> FloatArray:
        """(K,) stiffness T per phase, s; NaN for flight."""
        return self._arrays["stiffness"].copy()

    @property
    def on(self) -> IntArray:
        """(K, 2) footstep index under [left, right] foot, -1 while swinging."""
        return self._arrays["on"].copy()

    @property
    def boundary_times(self) -> FloatArray:
        """(K+1,) times of the phase boundaries, s, starting at 0."""
        return self._arrays["boundary_times"].copy()

    @property
    def footstep_array(self) -> FloatArray:
        """(M, 4) x, y, z, yaw of every foothold."""
        return self._arrays["footstep_array"].copy()

    @property
    def footstep_side(self) -> Int8Array:
        """(M,) int8 side of every foothold, 0 left / 1 right."""
        return self._arrays["footstep_side"].copy()

    @property
    def phase_gait(self) -> Int8Array:
        """(K,) gait code of every phase: 0 standing (the phases before the first single support and
        after the last one: the robot stands on both feet), else 1 walking / 2 running for the step
        the phase belongs to (a step is its single support and what follows it)."""
        codes = {"walk": 1, "run": 2}
        out = np.zeros(len(self.phases), dtype=np.int8)
        gaits = [*self.step_gait, "walk"]
        ss = np.flatnonzero(self.kind == SS)
        step = -1
        for i, kind in enumerate(self.kind):
            if kind == SS:
                step += 1
            if len(ss) and ss[0] <= i <= ss[-1]:
                out[i] = codes[gaits[min(step, len(gaits) - 1)]]
        return out


def build_sequence(
    step_gait: Sequence[str],
    footsteps: Sequence[Footstep],
    k: Stiffness,
    single_support: float,
    double_support: float,
    flight: float,
    start: float,
    stop: float,
) -> GaitSequence:
    """Phases for the given per-step gaits over ``footsteps`` (initial two + one per step + closing).

    Raises:
        InputError: a walk segment of a single step between two run segments (its one double support
            would have to end one transition and begin the next; at least two walking steps are needed).
    """
    n = len(step_gait)
    if len(footsteps) != n + 3:
        raise ValueError("footsteps must hold the two initial feet, one per step and the closing step")
    on = [0, 1]  # footstep index under left, right
    kinds: list[int] = [DS]
    durs: list[float] = [start]
    ons: list[tuple[int, int]] = [(on[0], on[1])]
    if step_gait and step_gait[0] == "run":
        kinds.append(DS)
        durs.append(double_support)
        ons.append((on[0], on[1]))
    gaits = [*step_gait, "walk"]  # the closing step always ends in double support
    for s, gait in enumerate(gaits):
        fs = footsteps[2 + s]
        swing = fs.side
        stance_on = list(on)
        stance_on[swing] = -1
        kinds.append(SS)
        durs.append(single_support)
        ons.append((stance_on[0], stance_on[1]))
        on[swing] = 2 + s
        if gait == "walk":
            kinds.append(DS)
            durs.append(double_support)
            ons.append((on[0], on[1]))
        else:
            kinds.append(FLIGHT)
            durs.append(flight)
            ons.append((-1, -1))
    kinds.append(DS)
    durs.append(stop)
    ons.append((on[0], on[1]))
    stiff = _assign_stiffness(kinds, k)
    phases = tuple(Phase(kd, d, T, o) for kd, d, T, o in zip(kinds, durs, stiff, ons, strict=True))
    return GaitSequence(phases, tuple(footsteps), tuple(step_gait))


def _assign_stiffness(kinds: list[int], k: Stiffness) -> list[float]:
    K = len(kinds)
    T = [math.nan] * K
    ds_t0 = [False] * K
    for i, kind in enumerate(kinds):
        if kind != SS:
            continue
        prev, nxt = kinds[i - 1], kinds[i + 1]
        if prev == DS and nxt == DS:
            T[i] = k.T_w
        elif prev == FLIGHT and nxt == FLIGHT:
            T[i] = k.T_r
        else:
            T[i] = k.T_t1
            j = i - 1 if prev == DS else i + 1
            if ds_t0[j]:
                raise InputError(
                    "gait",
                    "a single walking step between two running segments",
                    "at least two walking steps between running segments",
                )
            ds_t0[j] = True
    for i, kind in enumerate(kinds):
        if kind == DS:
            T[i] = k.T_t0 if ds_t0[i] else k.T_w
    return T
