"""Periodic orbits of the steady gaits, straight or turning, and the foot pattern that makes the
stride-mean CoM velocity equal the command.

For a steady step type (``walk``, ``run``) the horizontal state relative to the stance foot at the
SS start, ``s = (x - f, v)``, obeys per axis the affine step map of eqs. (3)-(6) of paper 001
(:mod:`.affine`): ``s' = A s + B d`` with ``d = f_next - f`` (``s'`` relative to the next foot). The
map is the same for x and y, so it commutes with rotations. In the frame of the stance foot (whose
yaw is the heading at its touchdown), with the heading turning by ``theta = omega tau`` per step and
the displacement ``d`` given in the landing foot's frame, ``S = (x, y, vx, vy)`` obeys::

    S'_loc = Q S_loc + (B kron I2) d,      Q = (I2 kron R(-theta)) (A kron I2)

Feet alternate sides, so the orbit has period two: from a left stance with displacements
``d_L`` (left -> right) then ``d_R`` (right -> left), ``S*_L = (I - Q^2)^-1 (Q b(d_L) + b(d_R))``.

Speed semantics (docs/locomotion.md): the stride-mean velocity is the CoM displacement over two
consecutive steps divided by their duration, in the heading frame at the middle of those steps. On a
straight orbit it is ``(d_L + d_R) / 2 tau`` whichever step the stride starts on. On a turning orbit
the CoM offset from the feet rotates too, so the two strides (starting on the left or on the right)
differ by a few mm/s; :meth:`Orbit.pattern` solves for the forward and lateral parts shared by
``d_L`` and ``d_R`` (the +/-w side offsets kept) that make the mean of the two equal the command.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from gaitshift.common.rotations import rot2
from gaitshift.models.arrays import FloatArray
from gaitshift.planners.locomotion.affine import phase_matrix
from gaitshift.planners.locomotion.steps import Anchor, StepType
from gaitshift.trajectory.contract import FLIGHT, LEFT

__all__ = ["Orbit", "feasible_yaw_rate", "step_matrix"]


def step_matrix(step: StepType) -> tuple[FloatArray, FloatArray]:
    """Relative one-step map of a step type, per axis: ``s' = A s + B d`` with s = (x - f, v) at the
    SS start and d = f_next - f. Returns A (2, 2), B (2,)."""
    cols = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])  # rows x, v; columns s_rel, s_v, d (own foot at 0)
    for ph in step.phases:
        M = phase_matrix(ph.kind, ph.stiffness, ph.duration)
        ends = (
            []
            if ph.zmp is None
            else [np.array([0.0, 0.0, 1.0 if a == Anchor.NEXT else 0.0]) for a in (ph.zmp.start, ph.zmp.end)]
        )
        stack = np.vstack([cols, *ends])
        cols = M[:, : len(stack)] @ stack
    cols[0] -= np.array([0.0, 0.0, 1.0])  # relative to the next foot
    return cols[:, :2].copy(), cols[:, 2].copy()


@dataclass(frozen=True)
class Orbit:
    """The periodic orbits of one steady step type: ``A``, ``B`` of :func:`step_matrix`."""

    step: StepType
    A: FloatArray
    B: FloatArray
    _cache: dict[tuple[float, float], tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]] = field(
        default_factory=dict, compare=False, repr=False
    )

    @staticmethod
    def of(step: StepType) -> Orbit:
        """Build the orbit maps of a steady step type."""
        A, B = step_matrix(step)
        return Orbit(step, A, B)

    def _maps(self, yaw_rate: float) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Q (4, 4), b = B kron I2 (4, 2), and (I - Q^2)^-1 (4, 4) for one yaw rate."""
        theta = yaw_rate * self.step.duration
        Q = np.kron(np.eye(2), rot2(-theta)) @ np.kron(self.A, np.eye(2))
        b = np.kron(self.B[:, None], np.eye(2))
        K = np.asarray(np.linalg.inv(np.eye(4) - Q @ Q), dtype=np.float64)
        return np.asarray(Q, dtype=np.float64), np.asarray(b, dtype=np.float64), K

    def _system(
        self, width: float, yaw_rate: float
    ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
        """Everything of :meth:`pattern` and :meth:`state` that does not depend on the velocity,
        cached per (width, yaw rate): the inverse of the mean stride map, its offset, and the orbit
        maps. The velocity only enters right-hand sides."""
        key = (width, yaw_rate)
        hit = self._cache.get(key)
        if hit is not None:
            return hit
        if len(self._cache) > 256:
            self._cache.clear()
        out = self._build_system(width, yaw_rate)
        self._cache[key] = out
        return out

    def _lag(self, yaw_rate: float) -> float:
        """Heading at the SS start minus the stance foot's yaw (its touchdown heading), rad."""
        td = self.step.duration if self.step.phases[-1].kind == FLIGHT else self.step.single_support
        return yaw_rate * (self.step.duration - td)

    def _build_system(
        self, width: float, yaw_rate: float
    ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
        tau = self.step.duration
        theta = yaw_rate * tau
        Q, b, K = self._maps(yaw_rate)
        R1, R2 = rot2(theta), rot2(2.0 * theta)
        back = rot2(-(self._lag(yaw_rate) + theta))
        # unknowns z = (a, b): d_L = (a, -w + b), d_R = (a, w + b); the side offsets +/-w stay
        dL = (np.eye(2), np.array([0.0, -width]))
        dR = (np.eye(2), np.array([0.0, width]))

        def stride(
            d1: tuple[FloatArray, FloatArray], d2: tuple[FloatArray, FloatArray]
        ) -> tuple[FloatArray, FloatArray]:
            """(M, c): the displacement of a stride with steps d1, d2 is M z + c (mid-stride frame)."""
            r = [(K @ (Q @ b @ d1[k] + b @ d2[k]))[:2] for k in (0, 1)]
            M = back @ (R1 @ d1[0] + R2 @ d2[0] + (R2 - np.eye(2)) @ r[0])
            c = back @ (R1 @ d1[1] + R2 @ d2[1] + (R2 - np.eye(2)) @ r[1])
            return M, c

        (ML, cL), (MR, cR) = stride(dL, dR), stride(dR, dL)
        # the mean of the two strides (starting left, starting right) equals the command
        Minv = np.asarray(np.linalg.inv(0.5 * (ML + MR)), dtype=np.float64)
        return Minv, np.asarray(0.5 * (cL + cR), dtype=np.float64), Q, b, K

    def pattern(self, velocity: npt.ArrayLike, width: float, yaw_rate: float = 0.0) -> tuple[FloatArray, FloatArray]:
        """Foot displacements (2,) each, in the landing foot's frame: ``d_L`` from a left stance and
        ``d_R`` from a right stance, such that the mean of the stride-mean velocities starting on
        either foot equals ``velocity`` (vx, vy) in the heading frame (module docstring)."""
        v = np.asarray(velocity, dtype=np.float64)
        Minv, c, _, _, _ = self._system(float(width), float(yaw_rate))
        z = Minv @ (2.0 * self.step.duration * v - c)
        return np.array([z[0], -width + z[1]]), np.array([z[0], width + z[1]])

    def state(
        self, velocity: npt.ArrayLike, width: float, side: int, yaw_rate: float = 0.0
    ) -> tuple[FloatArray, FloatArray]:
        """Orbit state at the SS start of a stance on ``side``, in that foot's frame: CoM position
        relative to the foot (2,) m and CoM velocity (2,) m/s, for the command ``velocity`` (vx, vy)
        m/s and ``yaw_rate`` rad/s with the foot pattern of :meth:`pattern`."""
        dL, dR = self.pattern(velocity, width, yaw_rate)
        _, _, Q, b, K = self._system(float(width), float(yaw_rate))
        d1, d2 = (dL, dR) if side == LEFT else (dR, dL)
        S = K @ (Q @ b @ d1 + b @ d2)
        return S[:2], S[2:]


def feasible_yaw_rate(
    orbit: Orbit, velocity: npt.ArrayLike, yaw_rate: float, width: float, bounds: tuple[float, float], max_stride: float
) -> float:
    """The yaw rate nearest to ``yaw_rate`` (same sign, smaller or equal magnitude) whose steady
    turning pattern (:meth:`Orbit.pattern`) keeps both lateral foot separations within ``bounds``
    (min, max) and the forward displacement within ``max_stride``: a turn tighter than that at this
    speed is not a periodic gait the feet can make. Bisection on |yaw_rate| (30 halvings)."""

    def ok(w: float) -> bool:
        dL, dR = orbit.pattern(velocity, width, w)
        seps = (-dL[1], dR[1])
        return all(bounds[0] - 1e-12 <= s <= bounds[1] + 1e-12 for s in seps) and abs(dL[0]) <= max_stride

    if ok(yaw_rate):
        return yaw_rate
    lo, hi = 0.0, abs(yaw_rate)
    if not ok(0.0):
        return 0.0
    sign = 1.0 if yaw_rate > 0 else -1.0
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ok(sign * mid) else (lo, mid)
    return sign * lo
