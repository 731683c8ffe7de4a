"""Horizontal CoM states as affine functions of the unknown foot displacements and ZMP knots.

Eq. (1) of paper 001 is linear and decoupled per horizontal axis. In a support phase of stiffness T
and duration tau, with the ZMP moving linearly from c0 to c1, its closed form (eqs. (3)-(4)) maps
the start state to the end state linearly, the same matrix for x and y::

    [x1]   [ C    T S   -C + T S / tau        1 - T S / tau ] [x0]
    [v1] = [ S/T  C     -1/tau - S/T + C/tau  (1 - C)/tau   ] [v0 c0 c1]^T,   C = cosh(tau/T), S = sinh(tau/T)

and in flight ``x1 = x0 + v0 tau``, ``v1 = v0`` (eqs. (5)-(6), horizontal part). With the foot
displacements and knots unknown, every point and state along a horizon is an affine function of
the unknown vector ``u`` (n,): :class:`Affine` holds ``value = const + J u`` with const (2,) [x, y]
and J (2, n). Foot displacements are unknown in the heading frame of the landing foot, so x and y
couple through the rotation; the dynamics themselves never couple them.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from gaitshift.models.arrays import FloatArray
from gaitshift.trajectory.contract import FLIGHT

__all__ = ["Affine", "phase_matrix", "propagate"]


@dataclass(frozen=True)
class Affine:
    """A point or vector of the plane, ``const + J @ u``: const (2,), J (2, n)."""

    const: FloatArray
    J: FloatArray

    @staticmethod
    def constant(value: npt.ArrayLike, n: int) -> Affine:
        """A known value (2,) independent of the n unknowns."""
        return Affine(np.asarray(value, dtype=np.float64).reshape(2).copy(), np.zeros((2, n)))

    @staticmethod
    def unknowns(index: int, n: int, basis: npt.ArrayLike | None = None) -> Affine:
        """``basis @ u[index:index+2]`` (basis (2, 2), identity by default) among n unknowns."""
        J = np.zeros((2, n))
        J[:, index : index + 2] = np.eye(2) if basis is None else np.asarray(basis, dtype=np.float64)
        return Affine(np.zeros(2), J)

    def __add__(self, other: Affine) -> Affine:
        return Affine(self.const + other.const, self.J + other.J)

    def __sub__(self, other: Affine) -> Affine:
        return Affine(self.const - other.const, self.J - other.J)

    def scale(self, a: float) -> Affine:
        """``a * self``."""
        return Affine(a * self.const, a * self.J)

    def shift(self, offset: npt.ArrayLike) -> Affine:
        """``self + offset`` for a known offset (2,)."""
        return Affine(self.const + np.asarray(offset, dtype=np.float64), self.J.copy())

    def value(self, u: FloatArray) -> FloatArray:
        """Evaluate for the unknowns ``u`` (n,). Returns (2,)."""
        return np.asarray(self.const + self.J @ u, dtype=np.float64)


@functools.lru_cache(maxsize=4096)
def phase_matrix(kind: int, stiffness: float, duration: float) -> FloatArray:
    """The (2, 4) matrix of eqs. (3)-(4) (support) or (5)-(6) (flight, horizontal part) mapping
    ``(x0, v0, c0, c1)`` to ``(x1, v1)`` over one phase (module docstring). Cached (read-only): the
    step types repeat the same few (stiffness, duration) pairs at every planning instant."""
    M = _phase_matrix(kind, stiffness, duration)
    M.flags.writeable = False
    return M


def _phase_matrix(kind: int, stiffness: float, duration: float) -> FloatArray:
    tau = duration
    if kind == FLIGHT:
        return np.array([[1.0, tau, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]])
    T = stiffness
    a = tau / T
    C, S = math.cosh(a), math.sinh(a)
    return np.array(
        [
            [C, T * S, -C + T * S / tau, 1.0 - T * S / tau],
            [S / T, C, -1.0 / tau - S / T + C / tau, (1.0 - C) / tau],
        ]
    )


def propagate(M: FloatArray, x: Affine, v: Affine, c0: Affine | None, c1: Affine | None) -> tuple[Affine, Affine]:
    """Apply a phase matrix ``M`` (2, 4) to affine states; ``c0``/``c1`` None in flight."""
    terms = (x, v) if c0 is None or c1 is None else (x, v, c0, c1)
    k = len(terms)
    const = M[:, :k] @ np.array([t.const for t in terms])  # (2, 2): rows x1, v1
    Js = np.array([t.J for t in terms])  # (k, 2, n)
    J = (M[:, :k] @ Js.reshape(k, -1)).reshape(2, *Js.shape[1:])  # (2, 2, n)
    return Affine(const[0], J[0]), Affine(const[1], J[1])
