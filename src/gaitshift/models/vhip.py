"""The simplified variable-height inverted pendulum (VHIP) of paper 003, §2.

Stance dynamics with zero rate of centroidal angular momentum, eq. (2)::

    p^{x,y} = c^{x,y} - c^z / (c''^z + g) * c''^{x,y}

with the CoM height c^z planned first (eqs. (3)-(6)) and the horizontal CoM then obtained from the
ZMP p by one tridiagonal solve (eqs. (7)-(14)).

Vertical CoM
    * flight, eq. (3): ballistic parabola ``z(t) = z_to + zd_to t - g t^2 / 2`` (the paper prints
      ``+ g t^2/2``; with z up and g > 0 the sign is minus). Eq. (4) generalises to different
      take-off and touchdown heights: ``zd_to = (z_td - z_to)/T_fly + g T_fly / 2``.
    * stance, eqs. (5)-(6): a sextic with seven boundary conditions (height, velocity and
      acceleration at both ends plus ``z(T_sup/2) = z_low``).

Horizontal CoM (discretised, step ``dt``)
    Eqs. (7)-(8) give the central second difference ``a_i = (c_{i+1} - 2 c_i + c_{i-1}) / dt^2``;
    plugged into eq. (2) this is eq. (9) **with the denominator (c''^z_i + g)** (the paper prints
    ``(c^z_i + g)``, a typo: the ratio must be z/(z''+g), a squared time). We multiply each row of
    eqs. (9)-(10) by ``w_i = (c''^z_i + g) dt^2 / c^z_i >= 0`` which gives the equivalent, never
    singular row::

        -c_{i-1} + (2 + w_i) c_i - c_{i+1} = w_i p_i                       (9')

    In flight (and at a contact switch where c''^z = -g) ``w_i = 0`` and (9') is the flight row
    eq. (14). Rows 0 and n are the velocity conditions of eq. (12); together they form eq. (13).
    The matrix is diagonally dominant (|2 + w| >= 2), so elimination without pivoting (our Thomas
    solver) is stable; LAPACK's gtsv/gttrf pivot anyway.

All heights in m, times in s, velocities m/s. Arrays are 1-D over samples unless stated.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import lapack, solve_banded

from ..errors import InfeasibleError

__all__ = [
    "FORCE_EPS", "Horizon", "VerticalGait", "stance_profiles", "flight_takeoff_velocity", "flight_height",
    "sextic_coefficients", "sextic_eval", "min_vertical_force", "check_pushing", "row_weights",
    "tridiagonal_system", "thomas", "solve_banded_tridiagonal", "solve_tridiagonal", "zmp_from_com",
]


# ============================================================================ vertical (eqs. 3-6)
def flight_takeoff_velocity(z_to: float, z_td: float, t_fly: float, g: float) -> tuple[float, float]:
    """Vertical take-off and touchdown velocities of a flight of ``t_fly`` s, eq. (4) generalised.

    ``zd_to = (z_td - z_to)/t_fly + g t_fly/2`` and ``zd_td = zd_to - g t_fly``; with
    ``z_td = z_to`` this is the paper's ``zd_to = g T_fly / 2 = -zd_td``. Returns (zd_to, zd_td), m/s.
    """
    zd_to = (z_td - z_to) / t_fly + 0.5 * g * t_fly
    return zd_to, zd_to - g * t_fly


def flight_height(z_to: float, zd_to: float, t: np.ndarray, g: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Ballistic CoM height, velocity and acceleration ``t`` s after take-off, eq. (3) (sign fixed).

    Returns (z, zd, zdd), each shaped like ``t``.
    """
    t = np.asarray(t, float)
    return z_to + zd_to * t - 0.5 * g * t * t, zd_to - g * t, np.full_like(t, -g)


def sextic_coefficients(T: float, z0: float, v0: float, a0: float, z_mid: float,
                        z1: float, v1: float, a1: float) -> np.ndarray:
    """Coefficients a_0..a_6 (in t, seconds) of the stance sextic, eqs. (5)-(6).

    Conditions: z(0)=z0, z'(0)=v0, z''(0)=a0, z(T/2)=z_mid, z(T)=z1, z'(T)=v1, z''(T)=a1.
    Solved in normalised time u = t/T: the first three coefficients follow from the t=0 conditions,
    the last four from a fixed 4x4 system. Returns shape (7,).
    """
    b = np.empty(7)
    b[0], b[1], b[2] = z0, v0 * T, 0.5 * a0 * T * T
    m = np.array([[1.0, 1.0, 1.0, 1.0],
                  [3.0, 4.0, 5.0, 6.0],
                  [6.0, 12.0, 20.0, 30.0],
                  [0.5**3, 0.5**4, 0.5**5, 0.5**6]])
    rhs = np.array([z1 - b[0] - b[1] - b[2],
                    v1 * T - b[1] - 2.0 * b[2],
                    a1 * T * T - 2.0 * b[2],
                    z_mid - b[0] - 0.5 * b[1] - 0.25 * b[2]])
    b[3:] = np.linalg.solve(m, rhs)
    return b / T ** np.arange(7)


def sextic_eval(coef: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Height, velocity and acceleration of the sextic ``coef`` (from :func:`sextic_coefficients`)."""
    t = np.asarray(t, float)
    c = np.asarray(coef, float)
    z = np.polynomial.polynomial.polyval(t, c)
    zd = np.polynomial.polynomial.polyval(t, c[1:] * np.arange(1, 7))
    zdd = np.polynomial.polynomial.polyval(t, c[2:] * np.arange(2, 7) * np.arange(1, 6))
    return z, zd, zdd


def min_vertical_force(coef: np.ndarray, T: float, g: float) -> tuple[float, float]:
    """Smallest ``z'' + g`` (vertical force per unit mass, m/s^2) over the open stance (0, T).

    Candidates: the interior critical points of z'' (real roots of the cubic z''') and a dense grid
    that excludes the end points (where z'' + g = 0 is allowed: zero force at a contact switch).
    Returns (min value, time of the minimum).
    """
    c = np.asarray(coef, float)
    c3 = c[3:] * np.array([6.0, 24.0, 60.0, 120.0])  # z''' coefficients
    roots = np.roots(c3[::-1]) if np.any(c3 != 0) else np.array([])
    crit = roots.real[(np.abs(roots.imag) < 1e-12) & (roots.real > 0) & (roots.real < T)]
    grid = np.linspace(0.0, T, 2001)[1:-1]
    ts = np.concatenate([grid, crit])
    _, _, zdd = sextic_eval(c, ts)
    k = int(np.argmin(zdd))
    return float(zdd[k] + g), float(ts[k])


def check_pushing(coef: np.ndarray, T: float, g: float, field: str, value: object) -> None:
    """Raise :class:`InfeasibleError` if the stance sextic needs a pulling ground force.

    The ground can only push: ``z'' + g > 0`` inside the stance, and ``z > 0``.
    """
    fmin, tmin = min_vertical_force(coef, T, g)
    if not fmin > 0:
        raise InfeasibleError(f"{field} = {value!r} is infeasible: the stance CoM height needs a pulling "
                              f"ground force (z''+g = {fmin:.3g} m/s^2 at t = {tmin:.3f} s of a "
                              f"{T:.3f} s stance); raise {field} or shorten the flight")
    z, _, _ = sextic_eval(coef, np.linspace(0.0, T, 201))
    if not np.all(z > 0):
        raise InfeasibleError(f"{field} = {value!r} is infeasible: the CoM height crosses the ground")


@dataclass(frozen=True, eq=False)
class VerticalGait:
    """The vertical CoM plan of a run (eqs. (3)-(6)): three stance sextics and the flight parabola.

    ``start``: standing height at rest -> take-off (State Switching 1); ``run``: touchdown ->
    take-off (cyclic running); ``stop``: touchdown -> standing height at rest (State Switching 3).
    All three pass through ``z_low`` at mid-stance. Coefficients in t (s), shape (7,) each.
    """

    g: float
    t_sup: float
    t_fly: float
    z_stand: float
    z_td: float
    z_to: float
    z_low: float
    a_td: float
    a_to: float
    zd_to: float
    zd_td: float
    start: np.ndarray
    run: np.ndarray
    stop: np.ndarray

    def _stance(self, coef: np.ndarray, j: np.ndarray, dt: float):
        return sextic_eval(coef, j * dt)

    def running_step(self, dt: float, n_fly: int, n_sup: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(z, zd, zdd) at samples j = 0..n_fly+n_sup of a step that starts at a take-off: flight
        for j < n_fly, stance sextic for n_fly <= j < n_fly+n_sup (touchdown at j = n_fly), and the
        take-off sample at the end. A sample exactly at a take-off belongs to the flight (z'' = -g,
        the force-free side of the switch), one exactly at a touchdown to the stance; with the default
        contact-switch accelerations (-g) both sides agree."""
        n = n_fly + n_sup
        j = np.arange(n + 1, dtype=float)
        out = [np.empty_like(j) for _ in range(3)]
        fl = j < n_fly
        for o, v in zip(out, flight_height(self.z_to, self.zd_to, j[fl] * dt, self.g)):
            o[fl] = v
        for o, v in zip(out, self._stance(self.run, j[~fl] - n_fly, dt)):
            o[~fl] = v
        out[0][n], out[1][n], out[2][n] = self.z_to, self.zd_to, -self.g
        return out[0], out[1], out[2]

    def start_horizon(self, dt: float, n_ds: int, n_sup: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(z, zd, zdd) at samples 0..n_ds+n_sup: constant standing height in double support, then the
        start sextic up to the first take-off (whose sample belongs to the flight, as in
        :meth:`running_step`)."""
        j = np.arange(n_ds + n_sup + 1, dtype=float)
        z, zd, zdd = np.full_like(j, self.z_stand), np.zeros_like(j), np.zeros_like(j)
        st = j >= n_ds
        z[st], zd[st], zdd[st] = self._stance(self.start, j[st] - n_ds, dt)
        z[-1], zd[-1], zdd[-1] = self.z_to, self.zd_to, -self.g      # the take-off sample: flight side
        return z, zd, zdd

    def stop_horizon(self, dt: float, n_fly: int, n_sup: int, n_ds: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(z, zd, zdd) at samples 0..n_fly+n_sup+n_ds from a take-off: flight, the stop sextic, then
        the standing height at rest in double support."""
        j = np.arange(n_fly + n_sup + n_ds + 1, dtype=float)
        z, zd, zdd = np.full_like(j, self.z_stand), np.zeros_like(j), np.zeros_like(j)
        fl = j < n_fly
        z[fl], zd[fl], zdd[fl] = flight_height(self.z_to, self.zd_to, j[fl] * dt, self.g)
        st = (j >= n_fly) & (j <= n_fly + n_sup)
        z[st], zd[st], zdd[st] = self._stance(self.stop, j[st] - n_fly, dt)
        return z, zd, zdd


def stance_profiles(heights, g: float, t_sup: float, t_fly: float) -> VerticalGait:
    """Build and check the vertical gait from ``heights`` (an object with ``stand``, ``touchdown``,
    ``takeoff``, ``z_low``, ``touchdown_acc``, ``takeoff_acc``; accelerations ``None`` = -g).

    Raises:
        InfeasibleError: a contact-switch acceleration below -g, or a ``z_low`` whose sextic needs a
            pulling ground force (z'' + g <= 0 inside a stance). The message names the field.
    """
    a_td = -g if heights.touchdown_acc is None else float(heights.touchdown_acc)
    a_to = -g if heights.takeoff_acc is None else float(heights.takeoff_acc)
    for name, a in (("heights.touchdown_acc", a_td), ("heights.takeoff_acc", a_to)):
        if a < -g:
            raise InfeasibleError(f"{name} = {a!r} is infeasible: below -gravity = {-g} m/s^2 the ground "
                                  "would have to pull")
    zd_to, zd_td = flight_takeoff_velocity(heights.takeoff, heights.touchdown, t_fly, g)
    zs, zl = heights.stand, heights.z_low
    start = sextic_coefficients(t_sup, zs, 0.0, 0.0, zl, heights.takeoff, zd_to, a_to)
    run = sextic_coefficients(t_sup, heights.touchdown, zd_td, a_td, zl, heights.takeoff, zd_to, a_to)
    stop = sextic_coefficients(t_sup, heights.touchdown, zd_td, a_td, zl, zs, 0.0, 0.0)
    for coef in (run, start, stop):
        check_pushing(coef, t_sup, g, "heights.z_low", zl)
    return VerticalGait(g, t_sup, t_fly, zs, heights.touchdown, heights.takeoff, zl, a_td, a_to,
                        zd_to, zd_td, start, run, stop)


# ============================================================================ horizontal (eqs. 7-14)
#: vertical force per unit mass below which a sample counts as force-free (flight row), m/s^2:
#: the sextic meets z'' = -g at a contact switch only up to rounding (~1e-13)
FORCE_EPS = 1e-9


def row_weights(z: np.ndarray, zdd: np.ndarray, g: float, dt: float) -> np.ndarray:
    """Row weights ``w_i = (z''_i + g) dt^2 / z_i`` of eq. (9'); 0 where ``z'' + g <= FORCE_EPS * g``
    (flight, and contact switches with zero vertical force)."""
    f = np.asarray(zdd, float) + g
    return np.where(f > FORCE_EPS * g, f * dt * dt / np.asarray(z, float), 0.0)


def tridiagonal_system(w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
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


def thomas(lower: np.ndarray, diag: np.ndarray, upper: np.ndarray, rhs: np.ndarray) -> np.ndarray:
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


def solve_banded_tridiagonal(lower: np.ndarray, diag: np.ndarray, upper: np.ndarray,
                             rhs: np.ndarray) -> np.ndarray:
    """The same solve with ``scipy.linalg.solve_banded`` ((1, 1) bands, LAPACK gtsv)."""
    ab = np.zeros((3, len(diag)))
    ab[0, 1:] = upper
    ab[1] = diag
    ab[2, :-1] = lower
    return solve_banded((1, 1), ab, rhs, check_finite=False, overwrite_ab=True)


def solve_tridiagonal(lower: np.ndarray, diag: np.ndarray, upper: np.ndarray, rhs: np.ndarray) -> np.ndarray:
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
    return x[3]


@dataclass(frozen=True, eq=False)
class Horizon:
    """Eq. (13) for one fixed vertical profile, factorised once (LAPACK gttrf) and solved many times.

    The running steps of a gait all share the same CoM height profile, hence the same matrix: the
    online generator factorises it once and each step costs one O(n) back-substitution (gttrs).

    Attributes:
        w: row weights (n+1,), see :func:`row_weights`.
        dt: sample step, s.
    """

    w: np.ndarray
    dt: float
    _lu: tuple = ()

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

    def rhs(self, p: np.ndarray, v0: np.ndarray, v1: np.ndarray) -> np.ndarray:
        """Right-hand side of eq. (13): ``[v0 dt, w_i p_i, v1 dt]``; p (n+1,) or (n+1, k)."""
        p = np.asarray(p, float)
        r = (self.w[:, None] * p) if p.ndim == 2 else self.w * p
        r = np.array(r, dtype=float, copy=True)
        r[0] = np.asarray(v0, float) * self.dt
        r[-1] = np.asarray(v1, float) * self.dt
        return r

    def solve_rhs(self, r: np.ndarray) -> np.ndarray:
        """Solve eq. (13) for a prepared right-hand side, shape (n+1,) or (n+1, k)."""
        dl, d, du, du2, ipiv = self._lu
        x, info = lapack.dgttrs(dl, d, du, du2, ipiv, r)
        if info != 0:  # pragma: no cover
            raise InfeasibleError(f"eq. (13) back-substitution failed (gttrs info {info})")
        return x

    def solve(self, p: np.ndarray, v0: np.ndarray, v1: np.ndarray) -> np.ndarray:
        """CoM samples c_0..c_n from ZMP samples ``p`` and the velocity conditions of eq. (12)."""
        return self.solve_rhs(self.rhs(p, v0, v1))

    def solve_transposed(self, r: np.ndarray) -> np.ndarray:
        """Solve ``Phi^T x = r`` (adjoint, used by the start/stop problem). Shape (n+1,)."""
        dl, d, du, du2, ipiv = self._lu
        x, info = lapack.dgttrs(dl, d, du, du2, ipiv, r, trans="T")
        if info != 0:  # pragma: no cover
            raise InfeasibleError(f"eq. (13) adjoint solve failed (gttrs info {info})")
        return x


def zmp_from_com(c: np.ndarray, z: np.ndarray, zdd: np.ndarray, acc: np.ndarray, g: float) -> np.ndarray:
    """ZMP of eq. (2): ``p = c - z / (z'' + g) * c''``. c, acc (N, 2); z, zdd (N,). Returns (N, 2)."""
    return c - (np.asarray(z) / (np.asarray(zdd) + g))[:, None] * acc
