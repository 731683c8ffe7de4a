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
from typing import Protocol

import numpy as np

from gaitshift.errors import InfeasibleError
from gaitshift.models.arrays import FloatArray
from gaitshift.models.sextic import sextic_coefficients, sextic_eval

__all__ = [
    "FORCE_EPS",
    "Heights",
    "VerticalGait",
    "check_pushing",
    "flight_height",
    "flight_takeoff_velocity",
    "min_vertical_force",
    "row_weights",
    "stance_profiles",
    "zmp_from_com",
]


# ============================================================================ vertical (eqs. 3-6)
def flight_takeoff_velocity(z_to: float, z_td: float, t_fly: float, g: float) -> tuple[float, float]:
    """Vertical take-off and touchdown velocities of a flight of ``t_fly`` s, eq. (4) generalised.

    ``zd_to = (z_td - z_to)/t_fly + g t_fly/2`` and ``zd_td = zd_to - g t_fly``; with
    ``z_td = z_to`` this is the paper's ``zd_to = g T_fly / 2 = -zd_td``. Returns (zd_to, zd_td), m/s.
    """
    zd_to = (z_td - z_to) / t_fly + 0.5 * g * t_fly
    return zd_to, zd_to - g * t_fly


def flight_height(z_to: float, zd_to: float, t: FloatArray, g: float) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Ballistic CoM height, velocity and acceleration ``t`` s after take-off, eq. (3) (sign fixed).

    Returns (z, zd, zdd), each shaped like ``t``.
    """
    t = np.asarray(t, float)
    return z_to + zd_to * t - 0.5 * g * t * t, zd_to - g * t, np.full_like(t, -g)


def min_vertical_force(coef: FloatArray, T: float, g: float) -> tuple[float, float]:
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


def check_pushing(coef: FloatArray, T: float, g: float, field: str, value: object) -> None:
    """Raise :class:`InfeasibleError` if the stance sextic needs a pulling ground force.

    The ground can only push: ``z'' + g > 0`` inside the stance, and ``z > 0``.
    """
    fmin, tmin = min_vertical_force(coef, T, g)
    if not fmin > 0:
        raise InfeasibleError(
            f"{field} = {value!r} is infeasible: the stance CoM height needs a pulling "
            f"ground force (z''+g = {fmin:.3g} m/s^2 at t = {tmin:.3f} s of a "
            f"{T:.3f} s stance); raise {field} or shorten the flight"
        )
    z, _, _ = sextic_eval(coef, np.linspace(0.0, T, 201))
    if not np.all(z > 0):
        raise InfeasibleError(f"{field} = {value!r} is infeasible: the CoM height crosses the ground")


class Heights(Protocol):
    """The CoM heights of a run (m) and the contact-switch accelerations (m/s^2, ``None`` = -g), as in
    ``VhipScenario.heights``."""

    @property
    def stand(self) -> float: ...
    @property
    def touchdown(self) -> float: ...
    @property
    def takeoff(self) -> float: ...
    @property
    def z_low(self) -> float: ...
    @property
    def touchdown_acc(self) -> float | None: ...
    @property
    def takeoff_acc(self) -> float | None: ...


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
    start: FloatArray
    run: FloatArray
    stop: FloatArray

    def _stance(self, coef: FloatArray, j: FloatArray, dt: float) -> tuple[FloatArray, FloatArray, FloatArray]:
        return sextic_eval(coef, j * dt)

    def running_step(self, dt: float, n_fly: int, n_sup: int) -> tuple[FloatArray, FloatArray, FloatArray]:
        """(z, zd, zdd) at samples j = 0..n_fly+n_sup of a step that starts at a take-off: flight
        for j < n_fly, stance sextic for n_fly <= j < n_fly+n_sup (touchdown at j = n_fly), and the
        take-off sample at the end. A sample exactly at a take-off belongs to the flight (z'' = -g,
        the force-free side of the switch), one exactly at a touchdown to the stance; with the default
        contact-switch accelerations (-g) both sides agree."""
        n = n_fly + n_sup
        j = np.arange(n + 1, dtype=float)
        out = [np.empty_like(j) for _ in range(3)]
        fl = j < n_fly
        for o, v in zip(out, flight_height(self.z_to, self.zd_to, j[fl] * dt, self.g), strict=True):
            o[fl] = v
        for o, v in zip(out, self._stance(self.run, j[~fl] - n_fly, dt), strict=True):
            o[~fl] = v
        out[0][n], out[1][n], out[2][n] = self.z_to, self.zd_to, -self.g
        return out[0], out[1], out[2]

    def start_horizon(self, dt: float, n_ds: int, n_sup: int) -> tuple[FloatArray, FloatArray, FloatArray]:
        """(z, zd, zdd) at samples 0..n_ds+n_sup: constant standing height in double support, then the
        start sextic up to the first take-off (whose sample belongs to the flight, as in
        :meth:`running_step`)."""
        j = np.arange(n_ds + n_sup + 1, dtype=float)
        z, zd, zdd = np.full_like(j, self.z_stand), np.zeros_like(j), np.zeros_like(j)
        st = j >= n_ds
        z[st], zd[st], zdd[st] = self._stance(self.start, j[st] - n_ds, dt)
        z[-1], zd[-1], zdd[-1] = self.z_to, self.zd_to, -self.g  # the take-off sample: flight side
        return z, zd, zdd

    def stop_horizon(self, dt: float, n_fly: int, n_sup: int, n_ds: int) -> tuple[FloatArray, FloatArray, FloatArray]:
        """(z, zd, zdd) at samples 0..n_fly+n_sup+n_ds from a take-off: flight, the stop sextic, then
        the standing height at rest in double support."""
        j = np.arange(n_fly + n_sup + n_ds + 1, dtype=float)
        z, zd, zdd = np.full_like(j, self.z_stand), np.zeros_like(j), np.zeros_like(j)
        fl = j < n_fly
        z[fl], zd[fl], zdd[fl] = flight_height(self.z_to, self.zd_to, j[fl] * dt, self.g)
        st = (j >= n_fly) & (j <= n_fly + n_sup)
        z[st], zd[st], zdd[st] = self._stance(self.stop, j[st] - n_fly, dt)
        return z, zd, zdd


def stance_profiles(heights: Heights, g: float, t_sup: float, t_fly: float) -> VerticalGait:
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
            raise InfeasibleError(
                f"{name} = {a!r} is infeasible: below -gravity = {-g} m/s^2 the ground would have to pull"
            )
    zd_to, zd_td = flight_takeoff_velocity(heights.takeoff, heights.touchdown, t_fly, g)
    zs, zl = heights.stand, heights.z_low
    start = sextic_coefficients(t_sup, zs, 0.0, 0.0, zl, heights.takeoff, zd_to, a_to)
    run = sextic_coefficients(t_sup, heights.touchdown, zd_td, a_td, zl, heights.takeoff, zd_to, a_to)
    stop = sextic_coefficients(t_sup, heights.touchdown, zd_td, a_td, zl, zs, 0.0, 0.0)
    for coef in (run, start, stop):
        check_pushing(coef, t_sup, g, "heights.z_low", zl)
    return VerticalGait(
        g, t_sup, t_fly, zs, heights.touchdown, heights.takeoff, zl, a_td, a_to, zd_to, zd_td, start, run, stop
    )


# ============================================================================ horizontal (eqs. 7-14)
#: vertical force per unit mass below which a sample counts as force-free (flight row), m/s^2:
#: the sextic meets z'' = -g at a contact switch only up to rounding (~1e-13)
FORCE_EPS = 1e-9


def row_weights(z: FloatArray, zdd: FloatArray, g: float, dt: float) -> FloatArray:
    """Row weights ``w_i = (z''_i + g) dt^2 / z_i`` of eq. (9'); 0 where ``z'' + g <= FORCE_EPS * g``
    (flight, and contact switches with zero vertical force)."""
    f = np.asarray(zdd, float) + g
    return np.where(f > FORCE_EPS * g, f * dt * dt / np.asarray(z, float), 0.0)


def zmp_from_com(c: FloatArray, z: FloatArray, zdd: FloatArray, acc: FloatArray, g: float) -> FloatArray:
    """ZMP of eq. (2): ``p = c - z / (z'' + g) * c''``. c, acc (N, 2); z, zdd (N,). Returns (N, 2)."""
    return c - (np.asarray(z) / (np.asarray(zdd) + g))[:, None] * acc
