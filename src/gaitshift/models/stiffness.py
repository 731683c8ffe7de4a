"""Stiffness T of the time-varying LIPM for walking, running and transitions (paper 001 §III).

All quantities are vertical and relative to the ZMP height (flat support), h the nominal CoM height.

* Walking: z'' = 0 at z = h gives ``T_w = sqrt(h/g)``.
* Running, eqs. (9)-(11): a half cycle SS(T_r, tau_SS) then F(tau_F) maps (h, v_0z) back to
  (h, v_0z). Unknowns (T_r, v_0z), two residuals, solved by Newton with the analytic Jacobian of the
  closed forms (3)-(6). ``v_r = v_0z`` is the touchdown vertical velocity (negative); by the time
  symmetry of the stance phase v_r = -g tau_F / 2, which the tests use as an independent check.
* Transition, eqs. (12)-(14): DS(T_t0, tau_DS) then SS(T_t1, tau_SS) maps (h, 0) to (h, -v_r), the
  take-off state of periodic running. Run-to-walk uses the same values in time-reversed order.

Everything is vectorised: pass arrays of timings to sweep a grid (Fig. 7 of 001).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TypeAlias, overload

import numpy as np

from gaitshift.errors import InputError, StiffnessError, number_in
from gaitshift.models.arrays import FloatArray, FloatLike, IntArray
from gaitshift.models.tvlip import support_map_1d

TOL = 1e-13
MAX_ITER = 50

#: residual (r0, r1) and Jacobian entries (j00, j01, j10, j11) of a 2x2 root problem, plain floats
Parts: TypeAlias = tuple[float, float, float, float, float, float]
#: the same, broadcast over arrays
PartsArrays: TypeAlias = tuple[FloatLike, FloatLike, FloatLike, FloatLike, FloatLike, FloatLike]


@dataclass(frozen=True)
class Stiffness:
    """Stiffness values (s) and the running touchdown velocity v_r (m/s, negative = downward)."""

    T_w: float
    T_r: float
    v_r: float
    T_t0: float
    T_t1: float

    def as_dict(self) -> dict[str, float]:
        return {"T_w": self.T_w, "T_r": self.T_r, "v_r": self.v_r, "T_t0": self.T_t0, "T_t1": self.T_t1}


#: the public call's physical ranges: CoM height, m; phase durations, s; gravity, m/s^2
HEIGHT_RANGE = (0.01, 100.0)
DURATION_RANGE = (1e-3, 60.0)
GRAVITY_RANGE = (0.01, 1000.0)


def _check_positive(**values: FloatLike) -> None:
    for name, value in values.items():
        arr = np.asarray(value, dtype=float)
        bad = ~(np.isfinite(arr) & (arr > 0))
        if np.any(bad):
            raise InputError(name, float(arr[bad].flat[0]) if arr.ndim else float(arr), "a finite number > 0")


def walking(height: FloatLike, gravity: float = 9.81) -> FloatLike:
    """T_w = sqrt(h/g), s (broadcasts)."""
    out: FloatLike = np.sqrt(np.asarray(height, float) / gravity)
    return out


def _running_parts(
    T: FloatLike, v0: FloatLike, height: FloatLike, single_support: FloatLike, flight: FloatLike, gravity: float
) -> PartsArrays:
    """Residual (r0, r1) of eqs. (9)-(11) and Jacobian entries (j00, j01, j10, j11) w.r.t. (T, v0)."""
    z1, v1, dz1, dv1 = support_map_1d(height, v0, T, single_support, gravity)
    z2 = z1 + v1 * flight - 0.5 * gravity * flight**2
    v2 = v1 - gravity * flight
    return (z2 - height, v2 - v0, dz1[2] + flight * dv1[2], dz1[1] + flight * dv1[1], dv1[2], dv1[1] - 1.0)


def _transition_parts(
    T0: FloatLike,
    T1: FloatLike,
    height: FloatLike,
    double_support: FloatLike,
    single_support: FloatLike,
    v_r: FloatLike,
    gravity: float,
) -> PartsArrays:
    """Residual (r0, r1) of eqs. (12)-(14) and Jacobian entries w.r.t. (T_t0, T_t1)."""
    z1, v1, dz1, dv1 = support_map_1d(height, 0.0, T0, double_support, gravity)
    z2, v2, dz2, dv2 = support_map_1d(z1, v1, T1, single_support, gravity)
    return (z2 - height, v2 + v_r, dz2[0] * dz1[2] + dz2[1] * dv1[2], dz2[2], dv2[0] * dz1[2] + dv2[1] * dv1[2], dv2[2])


def _stack(parts: PartsArrays) -> tuple[FloatArray, FloatArray]:
    r0, r1, j00, j01, j10, j11 = parts
    r = np.stack(np.broadcast_arrays(r0, r1), axis=-1)
    J = np.stack([np.stack(np.broadcast_arrays(j00, j01), -1), np.stack(np.broadcast_arrays(j10, j11), -1)], -2)
    return r, J


def running_residual(
    T: FloatLike, v0: FloatLike, height: FloatLike, single_support: FloatLike, flight: FloatLike, gravity: float = 9.81
) -> tuple[FloatArray, FloatArray]:
    """Residual of eqs. (9)-(11) and its Jacobian with respect to (T, v0).

    Returns ``(r, J)`` with r shape (..., 2) = (z_2 - h, v_2 - v_0) and J shape (..., 2, 2).
    """
    return _stack(_running_parts(T, v0, height, single_support, flight, gravity))


def transition_residual(
    T0: FloatLike,
    T1: FloatLike,
    height: FloatLike,
    double_support: FloatLike,
    single_support: FloatLike,
    v_r: FloatLike,
    gravity: float = 9.81,
) -> tuple[FloatArray, FloatArray]:
    """Residual of eqs. (12)-(14) and its Jacobian with respect to (T_t0, T_t1).

    Returns ``(r, J)`` with r = (z_2 - h, v_2 + v_r), shape (..., 2), and J shape (..., 2, 2).
    """
    return _stack(_transition_parts(T0, T1, height, double_support, single_support, v_r, gravity))


def _newton_scalar(
    parts_of: Callable[[float, float], PartsArrays], x0: float, x1: float
) -> tuple[float, float, float, int]:
    """Damped Newton for one point in plain floats (the same iteration as :func:`_newton`)."""

    def parts(y0: float, y1: float) -> Parts:
        r0, r1, j00, j01, j10, j11 = parts_of(y0, y1)  # floats in, floats out (math fast path)
        return float(r0), float(r1), float(j00), float(j01), float(j10), float(j11)

    r0, r1, a, b, c, d = parts(x0, x1)
    norm = max(abs(r0), abs(r1))
    it = 0
    while norm > TOL and it < MAX_ITER:
        det = a * d - b * c
        if det == 0.0 or not math.isfinite(det):
            break
        d0 = -(d * r0 - b * r1) / det
        d1 = -(-c * r0 + a * r1) / det
        alpha = 1.0
        for _ in range(30):
            y0, y1 = x0 + alpha * d0, x1 + alpha * d1
            trial: Parts | None
            try:
                trial = parts(y0, y1)
            except (OverflowError, ZeroDivisionError):
                trial = None
            if trial is not None and all(map(math.isfinite, trial)) and max(abs(trial[0]), abs(trial[1])) <= norm:
                break
            alpha /= 2
        else:
            break
        x0, x1 = y0, y1
        r0, r1, a, b, c, d = trial
        norm = max(abs(r0), abs(r1))
        it += 1
    return x0, x1, norm, it


def _newton(
    residual: Callable[[FloatArray], tuple[FloatArray, FloatArray]], x0: FloatArray
) -> tuple[FloatArray, FloatArray, IntArray]:
    """Damped Newton on ``residual(x) -> (r, J)`` for a batch x0 of shape (..., 2).

    Returns (x, |r|_inf, iterations) per batch element. The step is halved while it would make a
    stiffness non-positive or increase the residual norm.
    """
    x = x0.copy()
    r, J = residual(x)
    norm = np.max(np.abs(r), axis=-1)
    iters = np.zeros(norm.shape, dtype=int)
    for _ in range(MAX_ITER):
        active = norm > TOL
        if not np.any(active):
            break
        det = J[..., 0, 0] * J[..., 1, 1] - J[..., 0, 1] * J[..., 1, 0]
        det = np.where(np.abs(det) > 1e-300, det, 1e-300)
        dx0 = -(J[..., 1, 1] * r[..., 0] - J[..., 0, 1] * r[..., 1]) / det
        dx1 = -(-J[..., 1, 0] * r[..., 0] + J[..., 0, 0] * r[..., 1]) / det
        step = np.stack([dx0, dx1], -1) * active[..., None]
        alpha = np.ones(norm.shape)
        for _ in range(30):
            trial = x + alpha[..., None] * step
            r_t, J_t = residual(trial)
            n_t = np.max(np.abs(r_t), axis=-1)
            ok = (n_t <= norm) | ~active
            ok &= np.all(np.isfinite(r_t), axis=-1)
            if np.all(ok):
                break
            alpha = np.where(ok, alpha, alpha / 2)
        x = np.where(active[..., None], trial, x)
        r = np.where(active[..., None], r_t, r)
        J = np.where(active[..., None, None], J_t, J)
        norm = np.where(active, n_t, norm)
        iters += active
    return x, norm, iters


def _scalars(*values: FloatLike | None) -> bool:
    return all(np.ndim(v) == 0 for v in values if v is not None)


@overload
def solve_running(
    height: float, single_support: float, flight: float, gravity: float = 9.81
) -> tuple[float, float, float, int]: ...
@overload
def solve_running(
    height: FloatLike, single_support: FloatLike, flight: FloatLike, gravity: float = 9.81
) -> tuple[FloatLike, FloatLike, FloatLike, int | IntArray]: ...
def solve_running(
    height: FloatLike, single_support: FloatLike, flight: FloatLike, gravity: float = 9.81
) -> tuple[FloatLike, FloatLike, FloatLike, int | IntArray]:
    """Solve eqs. (9)-(11) for (T_r, v_r). Broadcasts.

    Returns ``(T_r, v_r, residual, iterations)``. The root exists and is unique in (0, T_w) for all
    positive timings (see docs/equations.md).
    """
    if _scalars(height, single_support, flight):
        h, tss, tf, g = float(height), float(single_support), float(flight), float(gravity)
        T, v, res, it = _newton_scalar(
            lambda a, b: _running_parts(a, b, h, tss, tf, g), 0.8 * math.sqrt(h / g), -0.5 * g * tf
        )
        return abs(T), v, res, it
    ha, tssa, tfa = np.broadcast_arrays(*(np.asarray(a, float) for a in (height, single_support, flight)))
    Twa = np.sqrt(ha / gravity)
    x0 = np.stack([0.8 * Twa, -0.5 * gravity * tfa], -1)
    x, resa, ita = _newton(lambda x: running_residual(x[..., 0], x[..., 1], ha, tssa, tfa, gravity), x0)
    return np.abs(x[..., 0]), x[..., 1], resa, ita


def solve_transition(
    height: FloatLike,
    double_support: FloatLike,
    single_support: FloatLike,
    v_r: FloatLike,
    gravity: float = 9.81,
    T_guess: FloatLike | None = None,
) -> tuple[FloatLike, FloatLike, FloatLike, int | IntArray]:
    """Solve eqs. (12)-(14) for (T_t0, T_t1). Broadcasts.

    Returns ``(T_t0, T_t1, residual, iterations)``.
    """
    if _scalars(height, double_support, single_support, v_r, T_guess):
        h, tds, tss, vr, g = (float(x) for x in (height, double_support, single_support, v_r, gravity))
        Tw = math.sqrt(h / g)
        t1 = float(T_guess) if T_guess is not None else 0.8 * Tw
        a, b, res, it = _newton_scalar(lambda a, b: _transition_parts(a, b, h, tds, tss, vr, g), 1.1 * Tw, t1)
        return abs(a), abs(b), res, it
    ha, tdsa, tssa, vra = np.broadcast_arrays(
        *(np.asarray(a, float) for a in (height, double_support, single_support, v_r))
    )
    Twa = np.sqrt(ha / gravity)
    t1a = np.broadcast_to(T_guess if T_guess is not None else 0.8 * Twa, ha.shape)
    x0 = np.stack([1.1 * Twa, t1a], -1)
    x, resa, ita = _newton(lambda x: transition_residual(x[..., 0], x[..., 1], ha, tdsa, tssa, vra, gravity), x0)
    return np.abs(x[..., 0]), np.abs(x[..., 1]), resa, ita


def stiffness(
    height: float, single_support: float, double_support: float, flight: float, gravity: float = 9.81
) -> Stiffness:
    """All stiffness values of paper 001 §III for one set of timings.

    Args:
        height: nominal CoM height h above the ZMP, m (> 0).
        single_support: tau_SS, s (> 0).
        double_support: tau_DS, s (> 0).
        flight: tau_F, s (> 0).
        gravity: g, m/s^2 (> 0).

    Raises:
        InputError: a non-positive or non-finite input.
        StiffnessError: no physical root (residual above 1e-10, or the CoM would reach the ground).
    """
    for name, value, bounds in (
        ("height", height, HEIGHT_RANGE),
        ("single_support", single_support, DURATION_RANGE),
        ("double_support", double_support, DURATION_RANGE),
        ("flight", flight, DURATION_RANGE),
        ("gravity", gravity, GRAVITY_RANGE),
    ):
        number_in(name, value, bounds)
    try:
        return _stiffness(float(height), float(single_support), float(double_support), float(flight), float(gravity))
    except (OverflowError, FloatingPointError, ZeroDivisionError) as exc:
        raise StiffnessError(
            "timings", (single_support, double_support, flight), f"timings the closed forms can evaluate ({exc})"
        ) from None


def _stiffness(height: float, single_support: float, double_support: float, flight: float, gravity: float) -> Stiffness:
    """:func:`stiffness` on checked numbers."""
    T_w = float(walking(height, gravity))
    T_r, v_r, res_r, _ = solve_running(height, single_support, flight, gravity)
    T_r, v_r = float(T_r), float(v_r)
    if not (res_r < 1e-10 and 0 < T_r < T_w):
        raise StiffnessError("flight", flight, f"timings with a real running stiffness (residual {float(res_r):.1e})")
    T_t0, T_t1, res_t, _ = solve_transition(height, double_support, single_support, v_r, gravity, T_guess=T_r)
    T_t0, T_t1 = float(T_t0), float(T_t1)
    if not (res_t < 1e-10 and math.isfinite(T_t0) and math.isfinite(T_t1)) or not _stays_above_ground(
        height, double_support, single_support, T_t0, T_t1, gravity
    ):
        raise StiffnessError(
            "double_support",
            double_support,
            f"timings for which the walk-run transition of eqs. (12)-(14) has a physical root "
            f"(none for tau_SS={single_support}, tau_F={flight}, h={height}; "
            f"try a longer double or single support or a shorter flight)",
        )
    return Stiffness(T_w=T_w, T_r=T_r, v_r=v_r, T_t0=T_t0, T_t1=T_t1)


def _stays_above_ground(h: float, tds: float, tss: float, T0: float, T1: float, g: float, n: int = 64) -> bool:
    """True if the transition keeps the CoM above the ZMP height (z > 0) throughout both phases."""
    t = np.linspace(0.0, 1.0, n)
    z1, _, _, _ = support_map_1d(h, 0.0, T0, tds * t, g)
    z_end, v_end, _, _ = support_map_1d(h, 0.0, T0, tds, g)
    z2, _, _, _ = support_map_1d(z_end, v_end, T1, tss * t, g)
    return bool(np.all(z1 > 0) and np.all(z2 > 0))


def sweep_running(
    height: float, single_support: FloatArray, flight: FloatArray, gravity: float = 9.81
) -> tuple[FloatArray, FloatArray, FloatArray, IntArray]:
    """Vectorised T_r over a grid (Fig. 7 of 001). ``single_support`` and ``flight`` broadcast.

    Returns ``(T_r, v_r, residual, iterations)`` arrays of the broadcast shape.
    """
    _check_positive(height=height, gravity=gravity, single_support=single_support, flight=flight)
    T_r, v_r, res, it = solve_running(height, single_support, flight, gravity)
    return np.asarray(T_r, float), np.asarray(v_r, float), np.asarray(res, float), np.asarray(it, np.intp)
