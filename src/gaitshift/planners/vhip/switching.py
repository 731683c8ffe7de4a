"""Start and stop of a run: the segmented cubic ZMP optimisation of paper 003 (§3.2, eqs. (15)-(18)).

State Switching 1 (start) covers a standing double support of duration T followed by the first
stance (and optionally a flight). During double support the ZMP of each horizontal axis is two cubic
Hermite segments (eqs. (16a)-(18)): from ``y0`` (rest, zero rate) to a knot ``(y_m, y'_m)`` at
``dT1`` and on to ``y1`` (zero rate) at ``T = dT1 + dT2``; in the stance it stays at ``y1``. The CoM
follows from eq. (13) with the velocity conditions ``c'(0) = 0`` and ``c'(end) = v_ref`` (16e-f);
the remaining condition of (16f), ``c(0) = c0``, is one linear equation in the ZMP samples. The ZMP
must stay in the double-support polygon (16g), here the box ``[lo, hi]`` per axis.

Eq. (16) has no objective: with three unknowns (dT1, y_m, y'_m) and one equation its solution is
not unique. We add the smoothness objective (documented in docs/vhip.md)::

    J = integral_0^T (y''(t))^2 dt          (ZMP "bending energy" of the two cubics)

For a fixed dT1 the ZMP samples are linear in (y_m, y'_m) and J is a convex quadratic, so the
equality-constrained minimum has a closed form (3x3 KKT system). Our solver scans dT1 on a grid,
vectorised over all candidates at once, and keeps the best feasible one; everything that depends
only on the horizon is prepared once (:class:`SwitchingSolver`). The linear functional
``c_0 = lambda . rhs`` comes from one adjoint solve ``Phi^T lambda = e_0``.

State Switching 3 (stop) is the same problem in reversed time: the rows of eq. (9') are symmetric
(alpha_i = chi_i), so reversing the samples maps a stop onto a start (see :func:`solve_stop`).

Eq. (18) as printed has ``2 dT x'_1`` in ``b_2``; the Hermite conditions need ``dT x'_1``
(see :func:`hermite_coefficients` and docs/vhip.md).

IPOPT (casadi, optional extra ``gaitshift[ipopt]``) solves the very same problem as a reference:
:func:`gaitshift.planners.vhip.switching_ipopt.solve_switching_ipopt`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from gaitshift.errors import InfeasibleError
from gaitshift.models.arrays import FloatArray, FloatLike
from gaitshift.models.tridiagonal import Horizon

__all__ = [
    "GRID",
    "MIN_SEGMENT",
    "StartSolver",
    "SwitchingProblem",
    "SwitchingSolution",
    "SwitchingSolver",
    "com_of",
    "hermite_coefficients",
    "smoothness",
    "solve_stop",
    "solve_switching",
    "stop_problem",
    "zmp_samples_xy",
]

#: shortest cubic segment as a share of T (keeps the Hermite basis well conditioned)
MIN_SEGMENT = 0.05
#: number of candidate knot times dT1 (2.1 ms apart for T = 1.2 s)
GRID = 513


def hermite_coefficients(dT: FloatLike, x0: FloatLike, xd0: FloatLike, x1: FloatLike, xd1: FloatLike) -> FloatArray:
    """Gamma of eqs. (17)-(18): cubic coefficients b_0..b_3 (in time since the segment start).
    Inputs broadcast; output shape (4, ...).

    ``b_2 = (3 (x1 - x0) - (2 xd0 + xd1) dT) / dT^2`` (corrected: the paper prints ``2 dT xd1``),
    ``b_3 = (2 (x0 - x1) + (xd0 + xd1) dT) / dT^3``.
    """
    b2 = (3.0 * (x1 - x0) - (2.0 * xd0 + xd1) * dT) / dT**2
    b3 = (2.0 * (x0 - x1) + (xd0 + xd1) * dT) / dT**3
    return np.stack(np.broadcast_arrays(np.asarray(x0, float), np.asarray(xd0, float), b2, b3))


def smoothness(
    dT1: FloatLike, dT2: FloatLike, y0: FloatLike, ym: FloatLike, ydm: FloatLike, y1: FloatLike
) -> FloatLike:
    """J = integral of y''^2 over both cubics, closed form (broadcasts). For a Hermite cubic of
    duration h from (a, va) to (b, vb): ``4/h^3 (3 D^2 - 3 h D (va + vb) + h^2 (va^2 + va vb + vb^2))``
    with D = b - a."""

    def seg(h: FloatLike, d: FloatLike, va: FloatLike, vb: FloatLike) -> FloatLike:
        return 4.0 / h**3 * (3 * d * d - 3 * h * d * (va + vb) + h * h * (va * va + va * vb + vb * vb))

    return seg(dT1, ym - y0, 0.0, ydm) + seg(dT2, y1 - ym, ydm, 0.0)


@dataclass(frozen=True, eq=False)
class SwitchingProblem:
    """One start problem, both horizontal axes [x, y].

    Attributes:
        w: row weights of eq. (9') over the horizon samples 0..n (n+1,).
        n_ds: double-support samples; the cubics span t in [0, n_ds dt], the stance follows.
        dt: sample step, s.
        y0, y1: ZMP at the start and at the end of double support (2,), m.
        c0: CoM at t = 0 (2,), m.
        v_end: CoM velocity at the last sample (2,), m/s (c'(0) = 0).
        lo, hi: ZMP bounds in double support (2,), m.
    """

    w: FloatArray
    n_ds: int
    dt: float
    y0: FloatArray
    y1: FloatArray
    c0: FloatArray
    v_end: FloatArray
    lo: FloatArray
    hi: FloatArray

    @property
    def T(self) -> float:
        """Duration of the double support, s."""
        return self.n_ds * self.dt

    def affine_constraint(self, horizon: Horizon | None = None) -> tuple[FloatArray, FloatArray]:
        """(g, K): ``c_0 = K + sum_i g_i p_i`` over double-support samples i = 0..n_ds, per axis.

        From ``c = Phi^{-1} rhs`` with ``rhs = [0, w_i p_i, v_end dt]``: ``c_0 = lambda . rhs`` with
        ``Phi^T lambda = e_0``. Returns g (n_ds+1,) and K (2,).
        """
        h = horizon or Horizon(self.w, self.dt)
        e0 = np.zeros(len(self.w))
        e0[0] = 1.0
        lam = h.solve_transposed(e0)
        gw = lam * self.w
        gw[0] = gw[-1] = 0.0
        g = gw[: self.n_ds + 1]
        K = lam[-1] * np.asarray(self.v_end, float) * self.dt + np.asarray(self.y1, float) * gw[self.n_ds + 1 :].sum()
        return g, K


@dataclass(frozen=True, eq=False)
class SwitchingSolution:
    """Solution per axis [x, y]: knot time dT1 (s), knot ZMP y_m (m) and rate y'_m (m/s), objective J,
    the ZMP over double support (n_ds+1, 2), the CoM over the horizon (n+1, 2), candidates tried."""

    dT1: FloatArray
    ym: FloatArray
    ydm: FloatArray
    J: FloatArray
    zmp: FloatArray
    com: FloatArray
    evaluations: int


class StartSolver(Protocol):
    """A solver of :class:`SwitchingProblem` s on one horizon (ours or the IPOPT reference)."""

    def solve(self, prob: SwitchingProblem) -> SwitchingSolution: ...


def _segment_extreme(
    h: FloatLike, x0: FloatLike, v0: FloatLike, x1: FloatLike, v1: FloatLike, which: int
) -> FloatArray:
    """Value at the interior stationary point of a Hermite cubic on [0, h] with one zero end rate
    (``which`` = 0: v0 = 0, the other root of y' is -2 b2 / (3 b3); 1: v1 = 0, the other root is
    v0 / (3 b3 h)), or NaN if that point is outside (0, h). Broadcasts."""
    b2 = (3.0 * (x1 - x0) - (2.0 * v0 + v1) * h) / (h * h)
    b3 = (2.0 * (x0 - x1) + (v0 + v1) * h) / (h * h * h)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = -2.0 * b2 / (3.0 * b3) if which == 0 else v0 / (3.0 * b3 * h)
        val = x0 + r * (v0 + r * (b2 + r * b3))
    return np.where((r > 0) & (r < h), val, np.nan)


class _KnotGrid:
    """Everything about the candidate knot times dT1 that does not depend on the boundary values:
    for each candidate, the sums of eq. (13)'s adjoint weights against the Hermite basis (from the
    prefix sums ``S[k, j] = sum_{i < j} g_i t_i^k``, in O(1) per candidate) and the Hessian of J.

    A problem (y0, y1, c0, v_end, bounds) then costs one vectorised pass over the grid
    (:meth:`solve`): the equality-constrained minimum of the quadratic J for every candidate, the ZMP
    range of every candidate from the single interior stationary point of each cubic, and the best
    feasible candidate.
    """

    def __init__(self, S: FloatArray, dt: float, n_ds: int, grid: int = GRID):
        T = n_ds * dt
        self.T = T
        hmin = MIN_SEGMENT * T
        h1 = np.linspace(hmin, T - hmin, grid)
        h2 = T - h1
        m = np.minimum(np.floor(h1 / dt + 1e-9).astype(int) + 1, n_ds + 1)  # samples with t_i <= h1
        P = S[:, m]  # (4, K) first-segment sums of g t^k
        Q = S[:, -1][:, None] - P  # second segment
        h1s = h1 * h1
        T1 = Q[1] - h1 * Q[0]  # second-segment sums of g tau^k, tau = t - h1
        T2 = Q[2] - 2 * h1 * Q[1] + h1s * Q[0]
        T3 = Q[3] - 3 * h1 * Q[2] + 3 * h1s * Q[1] - h1s * h1 * Q[0]
        i1, i2 = 1.0 / h1, 1.0 / h2
        i1s, i2s = i1 * i1, i2 * i2
        i1c, i2c = i1s * i1, i2s * i2
        a1 = 3 * P[2] * i1s - 2 * P[3] * i1c  # sum g h01 over the first segment
        a2 = 3 * T2 * i2s - 2 * T3 * i2c  # sum g h01 over the second segment
        # c_0 = K + sum g p = K + y0 (P0 - a1) + y1 a2 + A ym + B ydm
        A = Q[0] - a2 + a1
        B = (P[3] * i1s - P[2] * i1) + (T3 * i2s - 2 * T2 * i2 + T1)
        # J = q.H.q/2 + bvec.q + J0 over q = (ym, ydm), H = [[Huu, Huv], [Huv, Hvv]]
        Huu, Huv, Hvv = 24 * (i1c + i2c), 12 * (i2s - i1s), 8 * (i1 + i2)
        det = Huu * Hvv - Huv * Huv
        ia_u, ia_v = Hvv * A - Huv * B, Huu * B - Huv * A  # adj(H) (A, B)
        self.h1, self.h2 = h1, h2
        self.i1s, self.i2s, self.i1c, self.i2c = i1s, i2s, i1c, i2c
        self.y0_coef, self.y1_coef = P[0] - a1, a2
        self.A, self.B, self.Huu, self.Huv, self.Hvv, self.det = A, B, Huu, Huv, Hvv, det
        self.ia_u, self.ia_v = ia_u, ia_v
        with np.errstate(divide="ignore"):
            self.inv_aHa = 1.0 / (A * ia_u + B * ia_v)
        self.inv_det = 1.0 / det

    def solve(
        self, y0_: FloatArray, y1_: FloatArray, R0_: FloatArray, lo_: FloatArray, hi_: FloatArray
    ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, int]:
        """Best (dT1, ym, ydm, J) per axis, arrays (2,), and the number of candidates evaluated."""
        y0, y1, R0, lo, hi = (np.asarray(v, float)[:, None] for v in (y0_, y1_, R0_, lo_, hi_))
        h1, h2 = self.h1, self.h2
        R = R0 - y0 * self.y0_coef - y1 * self.y1_coef
        bu = -24 * (y0 * self.i1c + y1 * self.i2c)
        bv = 12 * (y0 * self.i1s - y1 * self.i2s)
        Huu, Huv, Hvv = self.Huu, self.Huv, self.Hvv
        ib_u, ib_v = Hvv * bu - Huv * bv, Huu * bv - Huv * bu  # adj(H) bvec
        with np.errstate(divide="ignore", invalid="ignore"):
            mu = -(R * self.det + self.A * ib_u + self.B * ib_v) * self.inv_aHa
            ym = -(ib_u + mu * self.ia_u) * self.inv_det
            ydm = -(ib_v + mu * self.ia_v) * self.inv_det
        J = (
            0.5 * (Huu * ym * ym + 2 * Huv * ym * ydm + Hvv * ydm * ydm)
            + bu * ym
            + bv * ydm
            + 12 * (y0 * y0 * self.i1c + y1 * y1 * self.i2c)
        )
        e1 = _segment_extreme(h1, y0, 0.0, ym, ydm, 0)
        e2 = _segment_extreme(h2, ym, ydm, y1, 0.0, 1)
        pmin = np.fmin(np.fmin(e1, e2), np.minimum(np.minimum(y0, y1), ym))
        pmax = np.fmax(np.fmax(e1, e2), np.maximum(np.maximum(y0, y1), ym))
        tol = 1e-12
        ok = np.isfinite(J) & (pmin >= lo - tol) & (pmax <= hi + tol)
        J = np.where(ok, J, np.inf)
        k = np.argmin(J, axis=1)
        ax = np.arange(2)
        Jk = J[ax, k]
        if not np.all(np.isfinite(Jk)):
            bad = int(np.argmin(np.isfinite(Jk)))
            excess = float(np.nanmin(np.maximum(pmax[bad] - hi[bad], lo[bad] - pmin[bad])))
            raise InfeasibleError(
                f"start/stop ({'xy'[bad]} axis): no ZMP inside the support polygon "
                f"[{float(lo[bad, 0]):.4f}, {float(hi[bad, 0]):.4f}] m reaches the requested speed (smallest "
                f"excursion outside {excess:.4f} m); lower the speed or lengthen the double support"
            )
        return h1[k], ym[ax, k], ydm[ax, k], Jk, 2 * len(h1)


class SwitchingSolver:
    """Our solver, prepared once per horizon (weights, n_ds, dt): the factorised eq. (13), the adjoint
    ``lambda`` and the prefix sums of ``lambda_i w_i t_i^k``. :meth:`solve` then costs O(n) for the
    output samples plus O(GRID) for the search, whatever the boundary values."""

    def __init__(self, w: FloatArray, n_ds: int, dt: float, horizon: Horizon | None = None):
        self.w = np.asarray(w, float)
        self.n_ds, self.dt = int(n_ds), float(dt)
        self.horizon = horizon or Horizon(self.w, self.dt)
        e0 = np.zeros(len(self.w))
        e0[0] = 1.0
        lam = self.horizon.solve_transposed(e0)
        gw = lam * self.w
        gw[0] = gw[-1] = 0.0
        self._g = gw[: n_ds + 1]
        self._lam_end = float(lam[-1])
        self._stance_sum = float(gw[n_ds + 1 :].sum())
        self.t = np.arange(n_ds + 1, dtype=np.float64) * dt
        self._S = np.zeros((4, n_ds + 2))
        np.cumsum(self._g[None, :] * self.t[None, :] ** np.arange(4)[:, None], axis=1, out=self._S[:, 1:])
        self._grid = _KnotGrid(self._S, self.dt, self.n_ds)

    def affine_constraint(self, prob: SwitchingProblem) -> tuple[FloatArray, FloatArray]:
        """(g, K) of :meth:`SwitchingProblem.affine_constraint` from the prepared adjoint."""
        K = self._lam_end * np.asarray(prob.v_end, float) * self.dt + np.asarray(prob.y1, float) * self._stance_sum
        return self._g, K

    def solve(self, prob: SwitchingProblem) -> SwitchingSolution:
        """Solve ``prob`` (same weights, n_ds and dt as this solver).

        Raises:
            InfeasibleError: no knot keeps the ZMP inside ``[lo, hi]`` for one of the axes.
        """
        _, K = self.affine_constraint(prob)
        dT1, ym, ydm, J, ev = self._grid.solve(prob.y0, prob.y1, np.asarray(prob.c0, float) - K, prob.lo, prob.hi)
        zmp = zmp_samples_xy(
            self.t, dT1, self.n_ds * self.dt, np.asarray(prob.y0, float), ym, ydm, np.asarray(prob.y1, float)
        )
        return SwitchingSolution(dT1, ym, ydm, J, zmp, com_of(prob, zmp, self.horizon), ev)


def zmp_samples_xy(
    t: FloatArray, dT1: FloatArray, T: float, y0: FloatArray, ym: FloatArray, ydm: FloatArray, y1: FloatArray
) -> FloatArray:
    """ZMP of eq. (16a) for both axes at times ``t`` (n,), from the cubic coefficients of eq. (18)
    (corrected b_2). Per-axis arrays (2,). Returns (n, 2)."""
    out = np.empty((len(t), 2))
    for k in range(2):
        h1 = float(dT1[k])
        b1 = hermite_coefficients(h1, y0[k], 0.0, ym[k], ydm[k])
        b2 = hermite_coefficients(T - h1, ym[k], ydm[k], y1[k], 0.0)
        m = int(np.searchsorted(t, h1, side="right"))  # samples with t <= h1
        tau1, tau2 = t[:m], t[m:] - h1
        out[:m, k] = b1[0] + tau1 * (b1[1] + tau1 * (b1[2] + tau1 * b1[3]))
        out[m:, k] = b2[0] + tau2 * (b2[1] + tau2 * (b2[2] + tau2 * b2[3]))
    return out


def solve_switching(prob: SwitchingProblem, horizon: Horizon | None = None) -> SwitchingSolution:
    """Our fast solver of the start problem (eqs. (15)-(18) plus the smoothness objective).

    Prepares a :class:`SwitchingSolver` for ``prob``'s horizon and solves; keep the solver when
    solving many problems on one horizon.
    """
    return SwitchingSolver(prob.w, prob.n_ds, prob.dt, horizon).solve(prob)


def com_of(prob: SwitchingProblem, zmp_ds: FloatArray, horizon: Horizon | None = None) -> FloatArray:
    """CoM over the horizon (n+1, 2) from the double-support ZMP (n_ds+1, 2) by eq. (13)."""
    h = horizon or Horizon(prob.w, prob.dt)
    n = len(prob.w)
    p = np.empty((n, 2))
    p[: prob.n_ds + 1] = zmp_ds
    p[prob.n_ds + 1 :] = prob.y1
    return h.solve(p, np.zeros(2), prob.v_end)


def stop_problem(
    w_stop: FloatArray,
    n_ds: int,
    dt: float,
    v_start: FloatArray,
    foot_offset: FloatArray,
    lo: FloatArray,
    hi: FloatArray,
) -> SwitchingProblem:
    """State Switching 3 as a start problem in reversed time, relative to the last stance foot A.

    The stop horizon runs from a take-off (velocity ``v_start``) through a flight, the last stance
    on A (ZMP at A = 0) and a double support of ``n_ds`` samples in which the ZMP moves from A to the
    midpoint of A and B = A + ``foot_offset``, ending at rest with the CoM over that midpoint.
    The rows of eq. (9') are symmetric, so reversing the samples gives a start problem with
    ``y0 = c0 = offset/2``, ``y1 = 0`` and ``v_end = -v_start``. ``lo``, ``hi`` bound the
    double-support ZMP relative to A.
    """
    mid = 0.5 * np.asarray(foot_offset, float)
    return SwitchingProblem(
        np.asarray(w_stop, float)[::-1].copy(),
        n_ds,
        dt,
        mid,
        np.zeros(2),
        mid,
        -np.asarray(v_start, float),
        np.asarray(lo, float),
        np.asarray(hi, float),
    )


def solve_stop(
    prob: SwitchingProblem, solver: StartSolver | None = None
) -> tuple[SwitchingSolution, FloatArray, FloatArray]:
    """Solve a stop built by :func:`stop_problem`; ``solver`` (ours by default, or
    :class:`~gaitshift.planners.vhip.switching_ipopt.IpoptSwitching`) must be prepared on the
    reversed weights.

    Returns (solution of the reversed problem, CoM (n+1, 2) in forward time relative to A,
    ZMP over the final double support (n_ds+1, 2) in forward time relative to A).
    """
    sol = (solver or SwitchingSolver(prob.w, prob.n_ds, prob.dt)).solve(prob)
    return sol, sol.com[::-1].copy(), sol.zmp[::-1].copy()
