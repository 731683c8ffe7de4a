"""Speed-guided target footholds: Algorithm 1 of paper 003 (§3.3, State Switching 2).

The horizon of one running step starts at a take-off (sample 0: CoM ``c_j(t_f)``, velocity
``c'_j(t_f)``), runs through the flight and the next stance and ends at the next take-off. With the
nominal ZMP of that stance (a foothold near the current support foot) eq. (13) gives a temporary CoM
that satisfies both velocity conditions of Algorithm 1, line 4:
``c'(t_0) = c'_j(t_f)`` and ``c'(t_f) = c'_cmd``. Its start generally misses the actual CoM by
``dc = c_temp(t_0) - c_j(t_f)``; the foothold is moved by ``-dc`` (line 13) until ``|dc| <= tol``.

How many iterations? Every row of eq. (9') has coefficients summing to ``w_i`` and right-hand side
``w_i p_i``; the velocity rows are differences. So shifting the whole ZMP of the horizon by ``d``
shifts the solution by exactly ``d``: ``dc`` is affine in the foothold with unit slope, and the
update of line 13 is a Newton step. It lands on the answer in **one** iteration (zero when the
nominal is already right); the residual after it is rounding, ~1e-16 m. docs/vhip.md has the numbers.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from gaitshift.errors import InfeasibleError
from gaitshift.models.arrays import FloatArray, IntArray

__all__ = ["MAX_ITER", "TOL", "FootholdResult", "StepHorizon", "target_foothold"]

#: Algorithm 1 tolerance on the CoM position mismatch, m
TOL = 1e-6
#: iteration budget; the acceptance bound of the project
MAX_ITER = 10


class StepHorizon(Protocol):
    """Eq. (13) of one step, ready to solve: row weights ``w`` (n+1,), sample step ``dt`` (s) and
    ``solve_rhs(r)`` for a prepared right-hand side (n+1, k) (e.g.
    :class:`~gaitshift.models.tridiagonal.Horizon`)."""

    @property
    def w(self) -> FloatArray: ...
    @property
    def dt(self) -> float: ...
    def solve_rhs(self, r: FloatArray) -> FloatArray: ...


@dataclass(frozen=True, eq=False)
class FootholdResult:
    """Target foothold (2,) [x, y] in m, the CoM over the horizon (n+1, 2), the iterations per axis
    (2,) and the final |dc| per axis (2,)."""

    foothold: FloatArray
    com: FloatArray
    iterations: IntArray
    residual: FloatArray


def target_foothold(
    horizon: StepHorizon,
    c_prev: FloatArray,
    v_prev: FloatArray,
    v_cmd: FloatArray,
    p_nom: FloatArray,
    zmp_shape: FloatArray | None = None,
    tol: float = TOL,
    max_iter: int = MAX_ITER,
) -> FootholdResult:
    """Algorithm 1: iterate the foothold until the CoM of eq. (13) starts at ``c_prev``.

    Args:
        horizon: eq. (13) of the step, factorised (samples 0..n, take-off to take-off).
        c_prev: CoM at the take-off ending the previous step, ``c_j(t_f)``, (2,) m.
        v_prev: CoM velocity there, ``c'_j(t_f)``, (2,) m/s.
        v_cmd: commanded take-off velocity at the end of this step, (2,) m/s.
        p_nom: nominal foothold, (2,) m.
        zmp_shape: optional ZMP offsets from the foothold over the horizon (n+1, 2) (e.g. a heel-to-toe
            roll); zero by default (the ZMP sits at the foothold during the stance).
        tol: |dc| tolerance per axis, m (1e-6 in the paper).
        max_iter: raise :class:`InfeasibleError` beyond this many updates.

    Returns:
        :class:`FootholdResult` with the target foothold and the CoM over the horizon.
    """
    c_prev = np.asarray(c_prev, float)
    p = np.array(p_nom, dtype=float)
    v0dt = np.asarray(v_prev, float) * horizon.dt
    v1dt = np.asarray(v_cmd, float) * horizon.dt
    w = horizon.w[:, None]
    base = None if zmp_shape is None else w * np.asarray(zmp_shape, float)  # does not move with p

    def com(p: FloatArray) -> FloatArray:  # eq. (13) with the ZMP at p during the stance
        rhs = w * p if base is None else base + w * p
        rhs[0], rhs[-1] = v0dt, v1dt
        return horizon.solve_rhs(rhs)

    c = com(p)  # line 4
    dc = c[0] - c_prev  # line 6
    iters = np.zeros(2, dtype=int)
    while True:
        active = np.abs(dc) > tol  # lines 7 / 12
        if not active.any():
            break
        if iters.max() >= max_iter:
            raise InfeasibleError(
                f"foothold iteration did not converge in {max_iter} iterations (|dc| = {np.abs(dc).max():.3g} m)"
            )
        p = p - np.where(active, dc, 0.0)  # line 13
        iters += active  # line 14
        c = com(p)  # line 15
        dc = c[0] - c_prev  # line 16
    return FootholdResult(p, c, iters, np.abs(dc))
