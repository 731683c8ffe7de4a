"""Gait sequences: contact phases (DS, SS, F) with durations and stiffness, and footsteps.

A plan starts and ends standing on both feet at rest. Footstep indices 0 and 1 are the initial left
and right feet; each step adds one foothold; a closing step places the trailing foot beside the last
one. Phase layout (paper 001, Fig. 2)::

    DS_start, [DS_t0 if step 1 runs], then per step: SS + (DS if walk else F),
    closing step: SS + DS, DS_stop

The stiffness of each support phase follows from its neighbours so that the vertical CoM motion
closes exactly (see :mod:`gaitshift.stiffness`):

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
from dataclasses import dataclass

import numpy as np

from .errors import InputError
from .stiffness import Stiffness
from .trajectory import DS, FLIGHT, LEFT, RIGHT, SS


@dataclass(frozen=True)
class Footstep:
    """A foothold: sole centre (x, y, z) in m, yaw in rad, side 0 left / 1 right."""

    x: float
    y: float
    z: float
    yaw: float
    side: int


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

    @property
    def kind(self) -> np.ndarray:
        """(K,) int8 phase kinds."""
        return np.array([p.kind for p in self.phases], dtype=np.int8)

    @property
    def duration(self) -> np.ndarray:
        """(K,) phase durations, s."""
        return np.array([p.duration for p in self.phases])

    @property
    def stiffness(self) -> np.ndarray:
        """(K,) stiffness T per phase, s; NaN for flight."""
        return np.array([p.stiffness for p in self.phases])

    @property
    def on(self) -> np.ndarray:
        """(K, 2) footstep index under [left, right] foot, -1 while swinging."""
        return np.array([p.on for p in self.phases], dtype=int)

    @property
    def boundary_times(self) -> np.ndarray:
        """(K+1,) times of the phase boundaries, s, starting at 0."""
        return np.concatenate([[0.0], np.cumsum(self.duration)])

    @property
    def footstep_array(self) -> np.ndarray:
        """(M, 4) x, y, z, yaw of every foothold."""
        return np.array([[f.x, f.y, f.z, f.yaw] for f in self.footsteps], dtype=float).reshape(-1, 4)

    @property
    def footstep_side(self) -> np.ndarray:
        """(M,) int8 side of every foothold, 0 left / 1 right."""
        return np.array([f.side for f in self.footsteps], dtype=np.int8)


def stride_profile(n_steps: int, max_stride: float, accelerate: int, decelerate: int) -> np.ndarray:
    """Forward stride of each step, m, shape (n_steps,): a trapezoid.

    The stride ramps linearly up over ``accelerate`` steps (max * k/(accelerate+1), k = 1..),
    holds ``max_stride``, and ramps down symmetrically over the last ``decelerate`` steps. Where the
    ramps overlap (short plans) the smaller value wins.
    """
    i = np.arange(1, n_steps + 1, dtype=float)
    up = np.minimum(i / (accelerate + 1), 1.0) if accelerate > 0 else np.ones(n_steps)
    j = n_steps + 1 - i
    down = np.minimum(j / (decelerate + 1), 1.0) if decelerate > 0 else np.ones(n_steps)
    return max_stride * np.minimum(up, down)


def initial_feet(step_width: float) -> list[Footstep]:
    """The two standing feet a plan starts on: left at (0, +w/2, 0), right at (0, -w/2, 0), yaw 0."""
    return [Footstep(0.0, step_width / 2, 0.0, 0.0, LEFT), Footstep(0.0, -step_width / 2, 0.0, 0.0, RIGHT)]


def closing_footstep(last: Footstep, step_width: float) -> Footstep:
    """The foothold beside ``last`` (same heading and height) on the other side."""
    sign = 1.0 if last.side == RIGHT else -1.0  # the new foot is on the other side
    return Footstep(last.x - sign * step_width * math.sin(last.yaw), last.y + sign * step_width * math.cos(last.yaw),
                    last.z, last.yaw, 1 - last.side)


def footsteps_from_profile(n_steps: int, first_swing: int, strides: np.ndarray, step_width: float,
                           yaw_rate: float = 0.0, step_height: float = 0.0) -> list[Footstep]:
    """Footholds for ``n_steps`` steps plus the closing step, after the two initial feet.

    The path centre advances by ``strides[i]`` along the heading, which turns by ``yaw_rate`` rad per
    step; each foothold sits ``step_width/2`` to its side of the path and ``step_height`` higher per step.
    """
    feet = initial_feet(step_width)
    last = feet[1 - first_swing]  # the stance foot of the first step
    cx = cy = cz = heading = 0.0
    side = first_swing
    for i in range(n_steps):
        heading += yaw_rate
        cx += strides[i] * math.cos(heading)
        cy += strides[i] * math.sin(heading)
        cz += step_height
        sign = 1.0 if side == LEFT else -1.0
        last = Footstep(cx - sign * step_width / 2 * math.sin(heading),
                        cy + sign * step_width / 2 * math.cos(heading), cz, heading, side)
        feet.append(last)
        side = 1 - side
    feet.append(closing_footstep(last, step_width))
    return feet


def build_sequence(step_gait: list[str], footsteps: list[Footstep], k: Stiffness, single_support: float,
                   double_support: float, flight: float, start: float, stop: float) -> GaitSequence:
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
    ons: list[tuple[int, int]] = [tuple(on)]
    if step_gait and step_gait[0] == "run":
        kinds.append(DS)
        durs.append(double_support)
        ons.append(tuple(on))
    gaits = list(step_gait) + ["walk"]  # the closing step always ends in double support
    for s, gait in enumerate(gaits):
        fs = footsteps[2 + s]
        swing = fs.side
        stance_on = list(on)
        stance_on[swing] = -1
        kinds.append(SS)
        durs.append(single_support)
        ons.append(tuple(stance_on))
        on[swing] = 2 + s
        if gait == "walk":
            kinds.append(DS)
            durs.append(double_support)
            ons.append(tuple(on))
        else:
            kinds.append(FLIGHT)
            durs.append(flight)
            ons.append((-1, -1))
    kinds.append(DS)
    durs.append(stop)
    ons.append(tuple(on))
    stiff = _assign_stiffness(kinds, k)
    phases = tuple(Phase(kd, d, T, o) for kd, d, T, o in zip(kinds, durs, stiff, ons))
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
                raise InputError("gait", "a single walking step between two running segments",
                                 "at least two walking steps between running segments")
            ds_t0[j] = True
    for i, kind in enumerate(kinds):
        if kind == DS:
            T[i] = k.T_t0 if ds_t0[i] else k.T_w
    return T
