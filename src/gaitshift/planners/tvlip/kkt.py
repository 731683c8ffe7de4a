"""The boundary problem of the TV-LIPM planner (paper 001 §II-B): exact dynamics, hinge on eq. (7).

Decision variables are the CoM position p_k, velocity v_k and ZMP c_k at every phase boundary
k = 0..K, per axis (d axes solved together: d = 2 for x, y, coupled by the foot yaw; d = 1 for z).
The problem

    min  1/2 sum_k ( w_r^2 |c_k - c_ref,k|^2 + w_h^2 |hinge_k(c_k)|^2 )
    s.t. (p_k+1, v_k+1) = Phi_k(p_k, v_k, c_k, c_k+1)      eqs. (3)-(4) support, (5)-(6) flight
         p_0, v_0, p_K, v_K fixed                            (start at rest, eq. (8) at the goal)

is solved by Gauss-Newton on the hinge of eq. (7): each iteration is one equality-constrained linear
least-squares problem whose KKT matrix, ordered boundary by boundary (p_k, v_k, c_k, then the
multipliers of the two dynamics rows of phase k), is banded, so each iteration costs O(K) through
LAPACK ``gbsv`` (the routine ``scipy.linalg.solve_banded`` calls). The constant part of the banded
matrix (dynamics rows, fixed values) is assembled once; an iteration only writes the ZMP Hessian
blocks of its active set. Unlike the paper, which penalises eqs. (3)-(6) and (8) softly, we impose
them exactly (they are linear in the unknowns for fixed T). The small regularisation w_r keeps the
ZMP near the sole centre where eq. (7) leaves it free (eq. (7) alone has no unique minimiser).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import lapack

from gaitshift.errors import InfeasibleError
from gaitshift.models.arrays import BoolArray, FloatArray, Int8Array, IntArray
from gaitshift.planners.tvlip.boxes import Boxes
from gaitshift.trajectory.contract import FLIGHT

__all__ = ["MAX_GN", "W_HINGE", "W_REG", "BoundaryPlan", "phase_coefficients", "solve_axes"]

W_REG = 1.0  # ZMP regularisation weight (1/m)
W_HINGE = 1e4  # eq. (7) hinge weight (1/m)
MAX_GN = 50


@dataclass(frozen=True)
class BoundaryPlan:
    """Solution at the phase boundaries: p, v, c of shape (K+1, d) (m, m/s, m; d = 3 for a whole plan,
    the solved axes for :func:`solve_axes`); Gauss-Newton iterations; max eq.-(7) violation (m) and
    the boundary index where it occurs."""

    p: FloatArray
    v: FloatArray
    c: FloatArray
    iterations: int
    violation: float
    violation_at: int


def phase_coefficients(
    kind: Int8Array, T: FloatArray, tau: FloatArray, g: float
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Scalar coefficients of eqs. (3)-(6) per phase: next = a . (p, v, c_k, c_k+1) + const_z e_z.

    ``kind`` (K,) phase kinds, ``T`` (K,) stiffness (s, NaN in flight), ``tau`` (K,) durations (s).
    Returns (ap, av, const) where ap, av have shape (K, 4) and const (K, 2) is the z-only term of
    (p_k+1, v_k+1). Flight phases have zero ZMP coefficients.
    """
    sup = kind != FLIGHT
    Ts = np.where(sup, T, 1.0)
    C, S = np.cosh(tau / Ts), np.sinh(tau / Ts)
    K = len(kind)
    ap, av, const = np.empty((K, 4)), np.empty((K, 4)), np.empty((K, 2))
    TS = Ts * S
    ap[:, 0] = np.where(sup, C, 1.0)
    ap[:, 1] = np.where(sup, TS, tau)
    ap[:, 2] = np.where(sup, -C + TS / tau, 0 * tau)
    ap[:, 3] = np.where(sup, 1 - TS / tau, 0 * tau)
    av[:, 0] = np.where(sup, S / Ts, 0 * tau)
    av[:, 1] = np.where(sup, C, 1.0)
    av[:, 2] = np.where(sup, -1 / tau - S / Ts + C / tau, 0 * tau)
    av[:, 3] = np.where(sup, (1 - C) / tau, 0 * tau)
    const[:, 0] = np.where(sup, g * Ts**2 * (1 - C), -0.5 * g * tau**2)
    const[:, 1] = np.where(sup, -g * Ts * S, -g * tau)
    return ap, av, const


def _dynamics_entries(ap: FloatArray, av: FloatArray, d: int, K: int) -> tuple[IntArray, IntArray, FloatArray]:
    """Constant part of the KKT matrix (dynamics rows and their transposes) as (row, col, val).

    Per phase k, axis a and row kind w (0: position, 1: velocity) the constraint
    ``x_{k+1} - coef . (p_k, v_k, c_k, c_{k+1}) = const`` has its multiplier at row r and touches the
    columns of p_k, v_k, c_k, c_{k+1} and of the state x_{k+1} (p or v)."""
    blk = 5 * d
    k = (np.arange(K) * blk)[None, None, None, :]
    a = np.arange(d)[:, None, None, None]
    offs = np.array([[0, d, 2 * d, blk + 2 * d, blk], [0, d, 2 * d, blk + 2 * d, blk + d]])[None, :, :, None]
    cols = k + a + offs  # (d, 2, 5, K)
    rows = np.broadcast_to(k + 3 * d + np.arange(2)[None, :, None, None] * d + a, cols.shape)
    vals = np.empty((2, 5, K))
    vals[0, :4] = -ap.T
    vals[1, :4] = -av.T
    vals[:, 4] = 1.0
    vals = np.broadcast_to(vals, cols.shape)
    return (
        np.concatenate([rows.ravel(), cols.ravel()]),
        np.concatenate([cols.ravel(), rows.ravel()]),
        np.concatenate([vals.ravel(), vals.ravel()]),
    )


class _HingeKKT:
    """The KKT system of one Gauss-Newton iteration, everything but the active set prepared once.

    Unknowns per boundary k: p_k, v_k, c_k (d each), then the 2 d multipliers of the dynamics of phase
    k; n = 5 d K + 3 d. Fixed unknowns (the end states, optionally c_0) are identity rows.
    """

    def __init__(
        self,
        coefficients: tuple[FloatArray, FloatArray, FloatArray],
        boxes: Boxes,
        fixed: FloatArray,
        const_scale: float,
        c_start: FloatArray | None,
    ) -> None:
        ap, av, const = coefficients
        K = len(ap)
        d = boxes.origin.shape[1]
        self.K, self.d, self.boxes = K, d, boxes
        blk = 5 * d
        self.n = n = K * blk + 3 * d
        r0, c0, v0_ = _dynamics_entries(ap, av, d, K)
        self.rhs_dyn = rhs_dyn = np.zeros(n)  # rhs of the dynamics rows
        k = np.arange(K)
        for a in range(d):
            rhs_dyn[k * blk + 3 * d + a] = const[:, 0] * const_scale
            rhs_dyn[k * blk + 4 * d + a] = const[:, 1] * const_scale
        fixed_idx = np.concatenate([np.arange(2 * d), K * blk + np.arange(2 * d)])
        fixed_val = fixed
        if c_start is not None:
            fixed_idx = np.concatenate([fixed_idx, 2 * d + np.arange(d)])
            fixed_val = np.concatenate([fixed_val, c_start])
        self.fixed_idx, self.fixed_val = fixed_idx, fixed_val
        is_fixed = np.zeros(n, bool)
        is_fixed[fixed_idx] = True
        keep = ~is_fixed[r0]
        self.r0, self.c0, self.v0 = r0[keep], c0[keep], v0_[keep]
        self.c_idx = (np.arange(K + 1) * blk)[:, None] + 2 * d + np.arange(d)[None, :]  # (K+1, d)
        hr = np.repeat(self.c_idx, d, axis=1).reshape(-1)
        hc = np.tile(self.c_idx, (1, d)).reshape(-1)
        self.h_free = ~is_fixed[hr]
        self.hr, self.hc = hr[self.h_free], hc[self.h_free]
        rows = np.concatenate([self.r0, self.hr, fixed_idx])
        cols = np.concatenate([self.c0, self.hc, fixed_idx])
        self.lower = int(np.max(rows - cols))
        self.upper = int(np.max(cols - rows))
        # gbsv storage: `lower` extra rows on top for the fill-in of the LU factors
        self.band = np.zeros((2 * self.lower + self.upper + 1, n))
        self.band[self.lower + self.upper + self.r0 - self.c0, self.c0] = self.v0 + 0.0
        self.band[self.lower + self.upper, fixed_idx] = 1.0
        self.h_pos = (self.lower + self.upper + self.hr - self.hc, self.hc)

    def hessian(self, active_lo: BoolArray, active_hi: BoolArray) -> tuple[FloatArray, FloatArray]:
        """Hessian blocks (K+1, d, d) ``w_r^2 I + w_h^2 R diag(active) R^T`` and the matching rhs
        (K+1, d) ``w_r^2 c_ref + w_h^2 R (bound + R^T origin)`` of the ZMP stationarity rows."""
        b, d = self.boxes, self.d
        R, org = b.rot, b.origin
        act = (active_lo | active_hi).astype(float)
        bound = np.where(active_hi, b.hi, b.lo) * act
        H = W_REG**2 * np.eye(d)[None] + W_HINGE**2 * np.einsum("kia,ka,kja->kij", R, act, R)
        rhs_c = W_REG**2 * org + W_HINGE**2 * np.einsum(
            "kia,ka->ki", R, act * (bound + np.einsum("kja,kj->ka", R, org))
        )
        return H, rhs_c

    def rhs(self, rhs_c: FloatArray) -> FloatArray:
        """The full right-hand side (n,) for the ZMP rows ``rhs_c`` (K+1, d)."""
        rhs = self.rhs_dyn.copy()
        rhs[self.c_idx.reshape(-1)] = rhs_c.reshape(-1)
        rhs[self.fixed_idx] = self.fixed_val
        return rhs

    def solve(self, active_lo: BoolArray, active_hi: BoolArray) -> FloatArray:
        """The KKT solution (n,) for one active set (banded LU, LAPACK gbsv)."""
        H, rhs_c = self.hessian(active_lo, active_hi)
        band = self.band.copy()
        band[self.h_pos] = H.reshape(-1)[self.h_free] + 0.0
        _, _, x, info = lapack.dgbsv(self.lower, self.upper, band, self.rhs(rhs_c), overwrite_ab=True)
        if info != 0:  # pragma: no cover - the KKT matrix of a feasible sequence is regular
            raise InfeasibleError(f"the boundary KKT system is singular (gbsv info {info})")
        out: FloatArray = x
        return out

    def solve_dense(self, active_lo: BoolArray, active_hi: BoolArray) -> FloatArray:
        """The same system by a dense LU (the O(K^3) baseline of ``gaitshift bench``)."""
        H, rhs_c = self.hessian(active_lo, active_hi)
        rows = np.concatenate([self.r0, self.hr, self.fixed_idx])
        cols = np.concatenate([self.c0, self.hc, self.fixed_idx])
        vals = np.concatenate([self.v0, H.reshape(-1)[self.h_free], np.ones(len(self.fixed_idx))])
        A = np.zeros((self.n, self.n))
        np.add.at(A, (rows, cols), vals)
        return np.asarray(np.linalg.solve(A, self.rhs(rhs_c)), dtype=np.float64)

    def unpack(self, x: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """(p, v, c), each (K+1, d), from the KKT solution."""
        idx = np.arange(self.K + 1) * 5 * self.d
        ar = np.arange(self.d)
        return x[idx[:, None] + ar], x[idx[:, None] + self.d + ar], x[self.c_idx]

    def local(self, c: FloatArray) -> FloatArray:
        """ZMP (K+1, d) in the box frames, ``R^T (c - origin)``."""
        u: FloatArray = np.einsum("kji,kj->ki", self.boxes.rot, c - self.boxes.origin)
        return u


def solve_axes(
    kind: Int8Array,
    T: FloatArray,
    tau: FloatArray,
    g: float,
    boxes: Boxes,
    p0: FloatArray,
    v0: FloatArray,
    pK: FloatArray,
    vK: FloatArray,
    const_scale: float,
    dense: bool = False,
    c_start: FloatArray | None = None,
    coefficients: tuple[FloatArray, FloatArray, FloatArray] | None = None,
) -> BoundaryPlan:
    """Solve the equality-constrained hinge least squares for d = boxes.origin.shape[1] axes.

    ``kind``, ``T``, ``tau`` (K,) describe the phases (:func:`phase_coefficients`); ``p0``, ``v0``,
    ``pK``, ``vK`` (d,) are the fixed end states (m, m/s). ``const_scale`` multiplies the gravity terms
    (1 for z, 0 for horizontal axes). ``dense`` solves the same KKT system with a dense LU (the O(K^3)
    baseline of ``gaitshift bench``). ``c_start`` (d,) fixes the ZMP at boundary 0 (re-planning keeps
    the ZMP continuous). ``coefficients`` are :func:`phase_coefficients` of the phases, when already
    computed (they do not depend on the axes).
    """
    coef = coefficients if coefficients is not None else phase_coefficients(kind, T, tau, g)
    kkt = _HingeKKT(coef, boxes, np.concatenate([p0, v0, pK, vK]), const_scale, c_start)
    K, d = kkt.K, kkt.d
    lo, hi = boxes.lo, boxes.hi
    active_lo = np.zeros((K + 1, d), bool)
    active_hi = np.zeros((K + 1, d), bool)
    solve = kkt.solve_dense if dense else kkt.solve
    it = 0
    for _ in range(MAX_GN):
        it += 1
        p, v, c = kkt.unpack(solve(active_lo, active_hi))
        u = kkt.local(c)
        new_hi = u > hi - 1e-12
        new_lo = u < lo + 1e-12
        # keep a constraint active while the solution sits on its bound (avoid cycling)
        new_hi |= active_hi & (u > hi - 1e-9)
        new_lo |= active_lo & (u < lo + 1e-9)
        if np.array_equal(new_hi, active_hi) and np.array_equal(new_lo, active_lo):
            break
        active_lo, active_hi = new_lo, new_hi
    u = kkt.local(c)
    viol = np.maximum(np.maximum(u - hi, lo - u), 0.0).max(axis=1)
    worst = int(np.argmax(viol))
    return BoundaryPlan(p, v, c, it, float(viol[worst]), worst)
