"""Start and stop of a VHIP run as plan segments (paper 003, State Switching 1 and 3).

* :func:`solve_start`: the standing double support and the first stance up to the first take-off.
  The segmented ZMP problem (:mod:`gaitshift.planners.vhip.switching`) is solved for the wanted
  take-off velocity; when no ZMP inside the feet reaches it, the fastest feasible fraction of it
  (bisection on the scale, 20 halvings).
* :func:`solve_stop`: from a take-off through the flight, the last stance on foot A and the final
  double support in which the ZMP moves to the midpoint of A and B (B one step width beside A),
  ending at rest.

Both return the segment's samples (horizontal CoM, ZMP, phase) for the plan buffer; positions in m,
velocities in m/s, arrays (2,) per axis [x, y].
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from gaitshift.errors import InfeasibleError
from gaitshift.models.arrays import FloatArray, Int8Array
from gaitshift.planners.vhip.horizons import VhipHorizons
from gaitshift.planners.vhip.switching import SwitchingProblem, SwitchingSolution, stop_problem
from gaitshift.planners.vhip.switching import solve_stop as solve_stop_problem
from gaitshift.trajectory.contract import DS, FLIGHT, LEFT, SS

__all__ = ["StartSegment", "StopSegment", "solve_start", "solve_stop"]


@dataclass(frozen=True, eq=False)
class StartSegment:
    """The start, samples 0..n_start+n_sup (the last one is the first take-off).

    Attributes:
        solution: the switching solution (knot, ZMP, CoM).
        scale: fraction of the wanted take-off velocity reached (1 unless infeasible).
        com: (n+1, 2) horizontal CoM; zmp: (n+1, 2) ZMP (NaN in flight); phase: (n+1,) int8.
    """

    solution: SwitchingSolution
    scale: float
    com: FloatArray
    zmp: FloatArray
    phase: Int8Array


@dataclass(frozen=True, eq=False)
class StopSegment:
    """The stop, samples 0..M after the take-off at sample 0 (which belongs to the previous step).

    Attributes:
        solution: the switching solution of the reversed problem.
        A, B: (2,) the last stance foothold and the foot placed beside it.
        com: (M+1, 2) horizontal CoM; zmp: (M+1, 2) ZMP (NaN in flight); phase: (M+1,) int8.
        n_ss_end: sample index (from the take-off) where the final double support starts.
    """

    solution: SwitchingSolution
    A: FloatArray
    B: FloatArray
    com: FloatArray
    zmp: FloatArray
    phase: Int8Array
    n_ss_end: int


def solve_start(h: VhipHorizons, want: FloatArray, side: int, y1: FloatArray) -> StartSegment:
    """Start from rest on both feet to a take-off from ``side`` (foothold ``y1``) with the take-off
    velocity ``want`` plus the lateral oscillation of ``side``, or the largest feasible fraction of
    ``want``.

    Raises:
        InfeasibleError: not even the start in place (zero velocity) keeps the ZMP in the feet.
    """
    n_ds, n_sup, dt, half = h.n_start, h.n_sup, h.dt, h.zmp_half
    lo = np.array([-half[0], -0.5 * h.width - half[1]])
    hi = -lo
    osc = np.array([0.0, h.oscillation(side)])

    def attempt(scale: float) -> SwitchingSolution:
        prob = SwitchingProblem(h.start_w, n_ds, dt, np.zeros(2), y1, np.zeros(2), scale * want + osc, lo, hi)
        return h.start_solver.solve(prob)

    try:
        sol, scale = attempt(1.0), 1.0
    except InfeasibleError:
        a, b = 0.0, 1.0
        sol = attempt(0.0)  # raises if even the in-place start is impossible
        for _ in range(20):
            mid = 0.5 * (a + b)
            try:
                sol, a = attempt(mid), mid
            except InfeasibleError:
                b = mid
        scale = a
    n = n_ds + n_sup
    w = h.start_w
    phase = np.where(np.arange(n + 1) < n_ds, DS, np.where(w > 0, SS, FLIGHT)).astype(np.int8)
    zmp = np.empty((n + 1, 2))
    zmp[:n_ds] = sol.zmp[:n_ds]
    zmp[n_ds:] = y1
    zmp[phase == FLIGHT] = np.nan
    return StartSegment(sol, scale, sol.com, zmp, phase)


def solve_stop(h: VhipHorizons, side: int, c_prev: FloatArray, v_prev: FloatArray) -> StopSegment:
    """Stop after the take-off at CoM ``c_prev`` with velocity ``v_prev``: the last stance on
    ``side``, then the other foot one step width beside it and the final double support to rest.

    Raises:
        InfeasibleError: no ZMP inside the feet brings the CoM to rest.
    """
    half = h.zmp_half
    sgn = 1.0 if side == LEFT else -1.0  # A on the left: B is to the right (-y)
    offset = np.array([0.0, -sgn * h.width])
    lo = np.array([-half[0], min(0.0, offset[1]) - half[1]])
    hi = np.array([half[0], max(0.0, offset[1]) + half[1]])
    prob = stop_problem(h.stop_w, h.n_stop, h.dt, v_prev, offset, lo, hi)
    sol, com_rel, zmp_rel = solve_stop_problem(prob, solver=h.stop_solver)
    delta = c_prev - com_rel[0]
    A, B = delta, delta + offset
    M = len(h.stop_w) - 1
    j = np.arange(M + 1)
    n_ss_end = h.n_fly + h.n_sup
    phase = np.where(j >= n_ss_end, DS, np.where(h.stop_w > 0, SS, FLIGHT)).astype(np.int8)
    zmp = np.where((phase == SS)[:, None], A[None, :], np.nan)
    zmp[n_ss_end:] = zmp_rel + delta
    return StopSegment(sol, A, B, com_rel + delta, zmp, phase, n_ss_end)
