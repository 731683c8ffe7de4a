"""Tridiagonal solves of eq. (13) of paper 003: the modified matrix, our Thomas algorithm, LAPACK.

Rows 1..n-1 are eq. (9') ``-c_{i-1} + (2 + w_i) c_i - c_{i+1} = w_i p_i`` (``w_i`` from
:func:`gaitshift.models.vhip.row_weights`); rows 0 and n are the velocity conditions of eq. (12).
The matrix is diagonally dominant (|2 + w| >= 2), so elimination without pivoting (the Thomas solver)
is stable; LAPACK's gtsv/gttrf pivot anyway. Cost O(n) per solve.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.linalg import lapack, solve_banded

from gaitshift.errors import InfeasibleError
from gaitshift.models.arrays import FloatArray, FloatLike, IntArray

__all__ = ["Horizon", "solve_banded_tridiagonal", "solve_tridiagonal", "thomas", "tridiagonal_system"]


def tridiagonal_system(w: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Bands (lower, diag, upper) of the modified matrix of eq. (13) for samples 0..n.

    ``w`` has shape (n+1,); its first and last entries are unused (velocity rows of eq. (12)).
    Returns lower (n,), diag (n+1,), upper (n,): row 0 is ``[-1, 1]``, row n is ``[-1, 1]``, rows
    1..n-1 are ``[-1, 2 + w_i, -1]`` (eq. (9') / eq. (14)).
    """
    n = len(w) - 1
    diag = 2.0 + np.asarray(w, float)
    diag[0], diag[n] = -1.0, 1.0
    upper = np.full(n, -1.0)
    upper[0] = 1.0
    lower = np.full(n, -1.0)
    return lower, diag, upper


def thomas(lower: FloatArray, diag: FloatArray, upper: FloatArray, rhs: FloatArray) -> FloatArray:
    """Our Thomas algorithm (tridiagonal LU without pivoting), O(n). ``rhs`` (n,) or (n, k)."""
    n = len(diag)
    rhs = np.asarray(rhs, float)
    lo, di, up = lower.tolist(), diag.tolist(), upper.tolist()
    if rhs.ndim == 1:
        d = rhs.tolist()
        cp = [0.0] * n
        dp = [0.0] * n
        cp[0] = up[0] / di[0] if n > 1 else 0.0
        dp[0] = d[0] / di[0]
        for i in range(1, n):
            m = di[i] - lo[i - 1] * cp[i - 1]
            if i < n - 1:
                cp[i] = up[i] / m
            dp[i] = (d[i] - lo[i - 1] * dp[i - 1]) / m
        x = [0.0] * n
        x[-1] = dp[-1]
        for i in range(n - 2, -1, -1):
            x[i] = dp[i] - cp[i] * x[i + 1]
        return np.array(x)
    cols = [thomas(lower, diag, upper, rhs[:, j]) for j in range(rhs.shape[1])]
    return np.stack(cols, axis=1)


def solve_banded_tridiagonal(lower: FloatArray, diag: FloatArray, upper: FloatArray, rhs: FloatArray) -> FloatArray:
    """The same solve with ``scipy.linalg.solve_banded`` ((1, 1) bands, LAPACK gtsv)."""
    ab = np.zeros((3, len(diag)))
    ab[0, 1:] = upper
    ab[1] = diag
    ab[2, :-1] = lower
    return np.asarray(solve_banded((1, 1), ab, rhs, check_finite=False, overwrite_ab=True), dtype=np.float64)


def solve_tridiagonal(lower: FloatArray, diag: FloatArray, upper: FloatArray, rhs: FloatArray) -> FloatArray:
    """Solve a tridiagonal system in O(n); the fastest of the measured options (see bench).

    ``gaitshift bench --only vhip.horizontal`` measures our :func:`thomas`, ``solve_banded`` and the
    LAPACK routine ``gtsv`` that ``solve_banded`` calls for (1, 1) bands. Compiled LAPACK beats the
    interpreted Thomas loop by about 2x at n = 100 and 20x at n = 5000; calling ``gtsv`` directly
    also skips ``solve_banded``'s argument handling (about 3x faster at n = 100). So ``gtsv`` it is.
    :func:`thomas` stays as the independent reference used by the tests.
    """
    x = lapack.dgtsv(lower, diag, upper, rhs)
    if x[-1] != 0:  # pragma: no cover - diagonally dominant matrices are never singular
        raise InfeasibleError(f"eq. (13) is singular (gtsv info {x[-1]})")
    out: FloatArray = x[3]
    return out


@dataclass(frozen=True, eq=False)
class Horizon:
    """Eq. (13) for one fixed vertical profile, factorised once (LAPACK gttrf) and solved many times.

    The running steps of a gait all share the same CoM height profile, hence the same matrix: the
    online generator factorises it once and each step costs one O(n) back-substitution (gttrs).

    Attributes:
        w: row weights (n+1,), see :func:`row_weights`.
        dt: sample step, s.
    """

    w: FloatArray
    dt: float
    _lu: tuple[FloatArray, FloatArray, FloatArray, FloatArray, IntArray] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        lower, diag, upper = tridiagonal_system(self.w)
        dl, d, du, du2, ipiv, info = lapack.dgttrf(lower, diag, upper)
        if info != 0:  # pragma: no cover - the matrix is diagonally dominant
            raise InfeasibleError(f"eq. (13) is singular (gttrf info {info})")
        object.__setattr__(self, "_lu", (dl, d, du, du2, ipiv))

    @property
    def n(self) -> int:
        """Index of the last sample (the horizon has n+1 samples)."""
        return len(self.w) - 1

    def rhs(self, p: FloatArray, v0: FloatLike, v1: FloatLike) -> FloatArray:
        """Right-hand side of eq. (13): ``[v0 dt, w_i p_i, v1 dt]``; p (n+1,) or (n+1, k)."""
        p = np.asarray(p, float)
        r = (self.w[:, None] * p) if p.ndim == 2 else self.w * p
        r = np.array(r, dtype=float, copy=True)
        r[0] = np.asarray(v0, float) * self.dt
        r[-1] = np.asarray(v1, float) * self.dt
        return r

    def solve_rhs(self, r: FloatArray) -> FloatArray:
        """Solve eq. (13) for a prepared right-hand side, shape (n+1,) or (n+1, k)."""
        dl, d, du, du2, ipiv = self._lu
        x: FloatArray
        x, info = lapack.dgttrs(dl, d, du, du2, ipiv, r)
        if info != 0:  # pragma: no cover
            raise InfeasibleError(f"eq. (13) back-substitution failed (gttrs info {info})")
        return x

    def solve(self, p: FloatArray, v0: FloatLike, v1: FloatLike) -> FloatArray:
        """CoM samples c_0..c_n from ZMP samples ``p`` and the velocity conditions of eq. (12)."""
        return self.solve_rhs(self.rhs(p, v0, v1))

    def solve_transposed(self, r: FloatArray) -> FloatArray:
        """Solve ``Phi^T x = r`` (adjoint, used by the start/stop problem). Shape (n+1,)."""
        dl, d, du, du2, ipiv = self._lu
        x: FloatArray
        x, info = lapack.dgttrs(dl, d, du, du2, ipiv, r, trans="T")
        if info != 0:  # pragma: no cover
            raise InfeasibleError(f"eq. (13) adjoint solve failed (gttrs info {info})")
        return x
