"""The foothold problem of one planning instant: foot displacements and ZMP knots that bring the
CoM onto a target state a few steps ahead, nearest to their nominal values, within their limits.

Along a horizon of steps (:class:`HorizonStep`) every state is affine in the unknowns ``u``
(:mod:`.affine`). The target gives linear conditions ``A u = b`` (a position and a velocity, i.e.
four scalar rows). Among their solutions we take the one nearest the nominal values::

    min_u  sum_j w_j (u_j - n_j)^2   s.t.  A u = b
    u = n + W^-1 A^T (A W^-1 A^T)^-1 (b - A n)                                  (minimum norm)

With exactly two unknown displacements per axis this is the unique deadbeat solution (paper 003's
"speed reached within two steps", generalised to every step type of :mod:`.steps`). If it leaves
the bounds ``lo <= u <= hi`` (kinematic limits, support polygons), the same problem with the bounds
is a small QP (daqp through qpsolvers). If that is infeasible, or there are fewer unknowns than
conditions, the target cannot be met exactly and we solve the bounded least-squares problem::

    min_u  |D (A u - b)|^2 + eps sum_j w_j (u_j - n_j)^2   s.t.  lo <= u <= hi

with ``D`` weighting the divergent component of the error most (the caller's row weights), by
``scipy.optimize.lsq_linear`` (``exact`` False).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt
import qpsolvers
from scipy.optimize import lsq_linear

from gaitshift.models.arrays import FloatArray
from gaitshift.planners.locomotion.affine import Affine, phase_matrix, propagate
from gaitshift.planners.locomotion.steps import Anchor, PhaseSpec, StepType

__all__ = ["EPS", "HorizonStep", "Row", "Solution", "Unknowns", "rollout", "solve"]

#: weight of the pull to the nominal values when the target cannot be met exactly
EPS = 1e-4


@dataclass
class Unknowns:
    """The scalar unknowns of one problem: nominal values, weights (1/m^2) and bounds."""

    nominal: list[float] = field(default_factory=list)
    weight: list[float] = field(default_factory=list)
    lo: list[float] = field(default_factory=list)
    hi: list[float] = field(default_factory=list)

    @property
    def n(self) -> int:
        """Number of scalar unknowns."""
        return len(self.weight)

    def add_pair(self, nominal: npt.ArrayLike, weight: float, lo: npt.ArrayLike, hi: npt.ArrayLike) -> int:
        """Register two unknowns (a plane vector); return the index of the first."""
        self.nominal += [float(x) for x in np.asarray(nominal, dtype=np.float64).reshape(2)]
        self.weight += [float(weight)] * 2
        self.lo += [float(x) for x in np.asarray(lo, dtype=np.float64).reshape(2)]
        self.hi += [float(x) for x in np.asarray(hi, dtype=np.float64).reshape(2)]
        return self.n - 2


@dataclass(frozen=True)
class Row:
    """A target condition ``expr = target`` (2 scalar rows) with a weight for the bounded fallback."""

    expr: Affine
    target: FloatArray
    weight: float


@dataclass(frozen=True)
class HorizonStep:
    """One step of the horizon: its type, the points its ZMP anchors refer to (affine), the phase
    index it starts at and the time already spent in that phase (s; the first step of a re-plan
    starts mid-phase)."""

    step: StepType
    own: Affine
    next: Affine
    knot: Affine | None = None
    rest: Affine | None = None
    first_phase: int = 0
    elapsed: float = 0.0

    def anchor(self, a: Anchor) -> Affine:
        """The point an anchor names."""
        point = {Anchor.OWN: self.own, Anchor.NEXT: self.next, Anchor.KNOT: self.knot, Anchor.REST: self.rest}[a]
        if point is None:
            raise ValueError(f"step {self.step.name} has no {a.name} point")
        return point

    def phases(self) -> list[tuple[PhaseSpec, float, float]]:
        """(phase, start offset into it, remaining duration) of the phases still ahead."""
        out = []
        for i, ph in enumerate(self.step.phases[self.first_phase :]):
            s0 = self.elapsed if i == 0 else 0.0
            out.append((ph, s0, ph.duration - s0))
        return out


def _zmp_ends(hs: HorizonStep, ph: PhaseSpec, s0: float) -> tuple[Affine, Affine] | tuple[None, None]:
    if ph.zmp is None:
        return None, None
    c0, c1 = hs.anchor(ph.zmp.start), hs.anchor(ph.zmp.end)
    if s0 > 0.0:  # the ZMP moves linearly: its value s0 into the phase
        a = s0 / ph.duration
        c0 = c0.scale(1.0 - a) + c1.scale(a)
    return c0, c1


def rollout(steps: list[HorizonStep], x: Affine, v: Affine) -> list[tuple[Affine, Affine]]:
    """CoM states (x, v) at the end of every step of the horizon, starting from (x, v)."""
    out = []
    for hs in steps:
        for ph, s0, rem in hs.phases():
            c0, c1 = _zmp_ends(hs, ph, s0)
            x, v = propagate(phase_matrix(ph.kind, ph.stiffness, rem), x, v, c0, c1)
        out.append((x, v))
    return out


@dataclass(frozen=True)
class Solution:
    """Values of the unknowns (n,) and whether the target was met exactly within the bounds."""

    u: FloatArray
    exact: bool


def _bounded_qp(
    A: FloatArray, b: FloatArray, nominal: FloatArray, w: FloatArray, lo: FloatArray, hi: FloatArray
) -> FloatArray | None:
    """``min sum w (u - n)^2  s.t.  A u = b, lo <= u <= hi`` (daqp), or None when infeasible."""
    try:
        x = qpsolvers.solve_qp(np.diag(w), -w * nominal, A=A, b=b, lb=lo, ub=hi, solver="daqp")
    except (ValueError, qpsolvers.SolverError):
        return None
    if x is None or np.max(np.abs(A @ x - b)) > 1e-9 or np.any(x < lo - 1e-9) or np.any(x > hi + 1e-9):
        return None
    return np.asarray(np.clip(x, lo, hi), dtype=np.float64)


def solve(rows: list[Row], unknowns: Unknowns) -> Solution:
    """Solve the problem of the module docstring."""
    nominal = np.asarray(unknowns.nominal, dtype=np.float64)
    lo, hi = np.asarray(unknowns.lo), np.asarray(unknowns.hi)
    if unknowns.n == 0:
        return Solution(nominal, exact=False)
    A = np.vstack([r.expr.J for r in rows])
    b = np.concatenate([np.asarray(r.target, dtype=np.float64) - r.expr.const for r in rows])
    w = np.asarray(unknowns.weight)
    resid = b - A @ nominal
    AW = A / w
    G = AW @ A.T
    u = None
    if unknowns.n >= len(b):
        try:
            u = nominal + AW.T @ np.linalg.solve(G, resid)
        except np.linalg.LinAlgError:  # rank-deficient: fewer independent unknowns than rows
            u = None
        if u is not None and np.linalg.norm(A @ u - b) > 1e-9 * max(1.0, float(np.linalg.norm(b))):
            u = None
    if u is None:  # fewer unknowns than rows: exact only if the rows are consistent (a plan re-solved)
        delta, *_ = np.linalg.lstsq(A, resid, rcond=None)
        u = nominal + delta
        if np.linalg.norm(A @ delta - resid) > 1e-9 * max(1.0, float(np.linalg.norm(b))):
            u = np.full_like(u, np.nan)
    if np.all(u >= lo - 1e-12) and np.all(u <= hi + 1e-12):
        return Solution(u, exact=True)
    if unknowns.n >= len(b):  # the same problem with the bounds: a small QP
        x = _bounded_qp(A, b, nominal, w, lo, hi)
        if x is not None:
            return Solution(x, exact=True)
    d = np.repeat([r.weight for r in rows], 2)
    sw = np.sqrt(EPS * w)
    M = np.vstack([A * d[:, None], np.diag(sw)])
    rhs = np.concatenate([b * d, sw * nominal])
    start = np.clip(nominal, lo, hi)
    res = lsq_linear(M, rhs, bounds=(lo, hi), method="bvls" if len(nominal) <= 12 else "trf")
    u = res.x if res.success else start
    return Solution(np.asarray(u, dtype=np.float64), exact=False)
