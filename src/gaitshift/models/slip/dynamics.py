"""3D spring-loaded inverted pendulum (3D-SLIP) dynamics, the running baseline of paper 001 §IV-C.

A point mass ``m`` rides on a massless spring leg of rest length ``l0`` and stiffness ``k``
(Wensing & Orin, IROS 2013). State ``s = (p, v)``, shape (6,), positions m, velocities m/s, z up.

* **Flight**: ballistic, ``p'' = -g e_z``.
* **Stance** on the foot point ``f`` (on the ground, f_z = 0), with ``r = p - f`` and ``L = |r|``:

      m p'' = k (l0 - L) r / L - m g e_z                                              (SLIP)

  Written as ``p'' = w(t) (p - f) - g e_z`` with ``w = (k/m)(l0/L - 1)``, this is exactly eq. (1) of
  paper 001 with the ZMP c = f and a *time-varying* stiffness ``1/T(t)^2 = w(t)``; the TV-LIPM
  replaces w(t) by the constant ``1/T_r^2``. That is why the two models can be compared at all.
* **Touchdown** is triggered by leg-angle geometry: the leg is held at the touchdown angles
  (theta, phi) during flight; the foot ``f = p + l0 d`` with the unit leg direction

      d(theta, phi) = (sin(theta) cos(phi), sin(phi), -cos(theta) cos(phi))

  touches the ground when ``p_z = l0 cos(theta) cos(phi)`` while falling. theta > 0 puts the foot ahead
  of the CoM, phi > 0 to its left (+y).
* **Lift-off** when the spring is back at its rest length, ``L = l0`` while extending.
* **TOF** (top of flight): ``v_z = 0`` while rising to falling.

The energy ``E = m |v|^2 / 2 + m g p_z + k (l0 - L)^2 / 2`` (spring term in stance only) is conserved;
:func:`energy` evaluates it, the tests check it.

A *half cycle* (:func:`simulate_half_cycle`) runs from one TOF to the next: flight, stance on one
foot, flight. Default parameters (:class:`SlipParams`) and where they come from: see docs/slip.md.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
from scipy.integrate import solve_ivp

from gaitshift.errors import InfeasibleError, InputError
from gaitshift.models.arrays import FloatArray

#: Integration tolerances. Tight: the tests ask for periodicity and energy to 1e-6.
RTOL = 1e-11
ATOL = 1e-12
METHOD = "DOP853"


@dataclass(frozen=True)
class SlipParams:
    """Physical parameters of the 3D-SLIP.

    Attributes:
        mass: m, kg. Only k/m enters the CoM motion; the mass scales forces and energy.
        stiffness: k, N/m (leg spring).
        leg_length: l0, m (spring rest length, CoM to foot).
        gravity: g, m/s^2.
    """

    mass: float = 80.0
    stiffness: float = 18600.0
    leg_length: float = 1.011
    gravity: float = 9.81

    def __post_init__(self) -> None:
        for name in ("mass", "stiffness", "leg_length", "gravity"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise InputError(f"slip.{name}", value, "a finite number > 0")

    @property
    def relative_stiffness(self) -> float:
        """Dimensionless leg stiffness k l0 / (m g)."""
        return self.stiffness * self.leg_length / (self.mass * self.gravity)


#: right-hand side ``f(t, s)`` of an ODE for solve_ivp, state s (6,)
Rhs = Callable[[float, FloatArray], FloatArray]
#: an event function ``e(t, s)`` for solve_ivp (solve_ivp reads its ``terminal`` and ``direction``)
EventFn = Callable[[float, FloatArray], float]


class DenseSegment(Protocol):
    """A solve_ivp solution with dense output: sample times ``t`` (n,), states ``y`` (6, n) and the
    interpolant ``sol(t) -> (6, len(t))``."""

    t: FloatArray
    y: FloatArray

    def sol(self, t: FloatArray) -> FloatArray: ...


def leg_direction(theta: float, phi: float) -> FloatArray:
    """Unit vector from the CoM to the foot at touchdown, shape (3,)."""
    return np.array([math.sin(theta) * math.cos(phi), math.sin(phi), -math.cos(theta) * math.cos(phi)])


def stance_rhs(params: SlipParams, foot: FloatArray) -> Rhs:
    """Right-hand side ``f(t, s)`` of the stance dynamics (SLIP) for solve_ivp, s shape (6,)."""
    k_m = params.stiffness / params.mass
    l0, g = params.leg_length, params.gravity
    fx, fy, fz = (float(c) for c in foot)

    def rhs(_t: float, s: FloatArray) -> FloatArray:
        rx, ry, rz = s[0] - fx, s[1] - fy, s[2] - fz
        L = np.sqrt(rx * rx + ry * ry + rz * rz)
        w = k_m * (l0 / L - 1.0)
        return np.array([s[3], s[4], s[5], w * rx, w * ry, w * rz - g])

    return rhs


def flight_rhs(params: SlipParams) -> Rhs:
    """Right-hand side of ballistic flight for solve_ivp."""
    g = params.gravity

    def rhs(_t: float, s: FloatArray) -> FloatArray:
        return np.array([s[3], s[4], s[5], 0.0, 0.0, -g])

    return rhs


def energy(params: SlipParams, states: FloatArray, foot: FloatArray | None = None) -> FloatArray:
    """Total mechanical energy, J, of states shape (..., 6); with ``foot`` the spring term is added
    where the leg is compressed (stance), shape (...)."""
    s = np.asarray(states, float)
    m, g = params.mass, params.gravity
    e = 0.5 * m * np.sum(s[..., 3:] ** 2, axis=-1) + m * g * s[..., 2]
    if foot is not None:
        L = np.linalg.norm(s[..., :3] - np.asarray(foot, float), axis=-1)
        e = e + 0.5 * params.stiffness * np.minimum(L - params.leg_length, 0.0) ** 2
    return np.asarray(e, dtype=np.float64)


@dataclass(frozen=True)
class HalfCycle:
    """One TOF-to-TOF half cycle of the SLIP.

    Attributes:
        state0: TOF state (6,) at t = 0.
        theta, phi: touchdown leg angles, rad.
        foot: foot point (3,), m.
        t_touchdown, t_liftoff, t_end: event times, s (t_end = next TOF).
        touchdown, liftoff, state1: states (6,) at touchdown, lift-off and the next TOF.
        segments: the three solve_ivp solutions (flight, stance, flight) with dense output, or ().
    """

    state0: FloatArray
    theta: float
    phi: float
    foot: FloatArray
    t_touchdown: float
    t_liftoff: float
    t_end: float
    touchdown: FloatArray
    liftoff: FloatArray
    state1: FloatArray
    segments: tuple[DenseSegment, ...] = field(default=(), repr=False)

    @property
    def stance_duration(self) -> float:
        return self.t_liftoff - self.t_touchdown

    @property
    def flight_before(self) -> float:
        """TOF to touchdown, s."""
        return self.t_touchdown

    @property
    def flight_after(self) -> float:
        """Lift-off to the next TOF, s."""
        return self.t_end - self.t_liftoff

    @property
    def flight_duration(self) -> float:
        """Flight time per step (both halves), s: the tau_F of paper 001."""
        return self.flight_before + self.flight_after

    def sample(self, t: FloatArray) -> FloatArray:
        """States (n, 6) at times ``t`` (n,) in [0, t_end] from the dense outputs."""
        if not self.segments:
            raise ValueError("half cycle integrated without dense output")
        t = np.asarray(t, float)
        out = np.empty((t.size, 6))
        bounds = (0.0, self.t_touchdown, self.t_liftoff, self.t_end)
        for i, sol in enumerate(self.segments):
            sel = (t >= bounds[i]) & ((t < bounds[i + 1]) if i < 2 else (t <= bounds[i + 1] + 1e-12))
            if np.any(sel):
                out[sel] = sol.sol(t[sel]).T
        return out

    def mirror_error(self) -> FloatArray:
        """Periodicity defect after the mirror map, shape (4,): (z1 - z0, vx1 - vx0, vy1 + vy0, vz1)."""
        s0, s1 = self.state0, self.state1
        return np.array([s1[2] - s0[2], s1[3] - s0[3], s1[4] + s0[4], s1[5]])


class HalfCycleFailed(Exception):
    """An event did not occur (the trial gait falls, never lands or never lifts off)."""


def _event(fn: EventFn, direction: int) -> EventFn:
    """Mark ``fn`` as a terminal solve_ivp event crossing zero in ``direction`` (solve_ivp reads the
    two attributes)."""
    event: Any = fn  # solve_ivp's protocol: attributes on the function object
    event.terminal = True
    event.direction = direction
    return fn


def simulate_half_cycle(
    params: SlipParams, state0: FloatArray, theta: float, phi: float, *, dense: bool = False, max_time: float = 3.0
) -> HalfCycle:
    """Integrate TOF -> touchdown -> lift-off -> TOF with solve_ivp and events.

    Args:
        params: SLIP parameters.
        state0: TOF state (6,) (v_z should be 0).
        theta, phi: touchdown leg angles, rad.
        dense: keep the dense outputs (for sampling and plotting).
        max_time: bound on each phase, s.

    Raises:
        InfeasibleError: the mass never lands, never lifts off, or hits the ground.
    """
    try:
        return integrate_half_cycle(params, np.asarray(state0, float), theta, phi, dense, max_time)
    except HalfCycleFailed as exc:
        raise InfeasibleError(f"SLIP half cycle failed: {exc}") from None


def integrate_half_cycle(
    params: SlipParams, s0: FloatArray, theta: float, phi: float, dense: bool, max_time: float
) -> HalfCycle:
    """:func:`simulate_half_cycle` for a float state ``s0`` (6,), raising :class:`HalfCycleFailed`
    (cheap to catch inside an optimiser) instead of :class:`InfeasibleError`."""
    l0 = params.leg_length
    h_td = l0 * math.cos(theta) * math.cos(phi)
    if not h_td > 0:
        raise HalfCycleFailed("touchdown height l0 cos(theta) cos(phi) <= 0")
    opts: dict[str, Any] = {"method": METHOD, "rtol": RTOL, "atol": ATOL, "dense_output": dense}

    # flight until the foot, held at (theta, phi), reaches the ground
    touch = _event(lambda _t, s: s[2] - h_td, -1)
    if s0[2] <= h_td:
        raise HalfCycleFailed(f"TOF height {s0[2]:.4f} m not above the touchdown height {h_td:.4f} m")
    f1 = solve_ivp(flight_rhs(params), (0.0, max_time), s0, events=touch, **opts)
    if f1.status != 1 or not len(f1.t_events[0]):
        raise HalfCycleFailed("no touchdown")
    t_td = float(f1.t_events[0][0])
    s_td = f1.y_events[0][0]
    foot = s_td[:3] + l0 * leg_direction(theta, phi)
    foot[2] = 0.0

    # stance until the spring is back at rest length (or the mass hits the ground)
    lift = _event(lambda _t, s: np.sqrt((s[0] - foot[0]) ** 2 + (s[1] - foot[1]) ** 2 + s[2] ** 2) - l0, 1)
    ground = _event(lambda _t, s: s[2], -1)
    st = solve_ivp(stance_rhs(params, foot), (t_td, t_td + max_time), s_td, events=(lift, ground), **opts)
    if st.status != 1 or not len(st.t_events[0]):
        raise HalfCycleFailed("no lift-off")
    t_lo = float(st.t_events[0][0])
    s_lo = st.y_events[0][0]
    if s_lo[5] <= 0:
        raise HalfCycleFailed("lift-off while falling (no flight after stance)")

    # flight until the next top of flight
    top = _event(lambda _t, s: s[5], -1)
    f2 = solve_ivp(flight_rhs(params), (t_lo, t_lo + max_time), s_lo, events=top, **opts)
    if f2.status != 1 or not len(f2.t_events[0]):
        raise HalfCycleFailed("no top of flight")
    t_end = float(f2.t_events[0][0])
    s1 = f2.y_events[0][0]
    segs = (f1, st, f2) if dense else ()
    return HalfCycle(s0, float(theta), float(phi), foot, t_td, t_lo, t_end, s_td, s_lo, s1, segs)
