"""3D spring-loaded inverted pendulum (3D-SLIP), the running baseline of paper 001 §IV-C.

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

A *half cycle* runs from one TOF to the next: flight, stance on one foot, flight. It is *periodic
with the mirror-symmetric lateral condition* when the next TOF equals the first after the mirror
map y -> -y about the running mid-line: equal height, equal forward speed, opposite lateral velocity
(the mid-line is where it must be: half-way between the two TOF positions). The next half cycle is
then the mirror image on the other foot.

Periodic gait search (:func:`periodic_half_cycle`). As in paper 001 §IV-C (after Wensing & Orin),
the unknowns are the TOF height z0, the lateral TOF velocity vy0 and the contact angles
(theta, phi), given the desired forward TOF speed vx0 (3.5 m/s in the paper); the stance and flight
durations follow from the events of the integration (solve_ivp with events) and are reported.
Residuals, solved by ``scipy.optimize.least_squares`` (Levenberg-Marquardt, finite differences,
so every evaluation is one half-cycle integration):

    z1 - z0,  vx1 - vx0,  vy1 + vy0               periodicity under the mirror map
    t_F - tau_F                                   flight time per step = the desired tau_F
    (f_y - (y0 + y1)/2) + w                       foot w to the right of the mid-line

Periodicity alone leaves a two-parameter family (energy conservation makes z1 = z0 follow from the
two velocity conditions, so only two of the first three are independent); the flight time and the
step width pick one member. Fixing the touchdown height instead of tau_F does not work: with the leg
angle fixed by h, a periodic gait exists only for one stiffness.

Default parameters (:class:`SlipParams`) and where they come from: see docs/slip.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import least_squares

from ..errors import InfeasibleError, InputError

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


def leg_direction(theta: float, phi: float) -> np.ndarray:
    """Unit vector from the CoM to the foot at touchdown, shape (3,)."""
    return np.array([math.sin(theta) * math.cos(phi), math.sin(phi), -math.cos(theta) * math.cos(phi)])


def stance_rhs(params: SlipParams, foot: np.ndarray):
    """Right-hand side ``f(t, s)`` of the stance dynamics (SLIP) for solve_ivp, s shape (6,)."""
    k_m = params.stiffness / params.mass
    l0, g = params.leg_length, params.gravity
    fx, fy, fz = (float(c) for c in foot)

    def rhs(t, s):
        rx, ry, rz = s[0] - fx, s[1] - fy, s[2] - fz
        L = np.sqrt(rx * rx + ry * ry + rz * rz)
        w = k_m * (l0 / L - 1.0)
        return np.array([s[3], s[4], s[5], w * rx, w * ry, w * rz - g])

    return rhs


def flight_rhs(params: SlipParams):
    """Right-hand side of ballistic flight for solve_ivp."""
    g = params.gravity

    def rhs(t, s):
        return np.array([s[3], s[4], s[5], 0.0, 0.0, -g])

    return rhs


def energy(params: SlipParams, states: np.ndarray, foot: np.ndarray | None = None) -> np.ndarray:
    """Total mechanical energy, J, of states shape (..., 6); with ``foot`` the spring term is added
    where the leg is compressed (stance), shape (...)."""
    s = np.asarray(states, float)
    m, g = params.mass, params.gravity
    e = 0.5 * m * np.sum(s[..., 3:] ** 2, axis=-1) + m * g * s[..., 2]
    if foot is not None:
        L = np.linalg.norm(s[..., :3] - np.asarray(foot, float), axis=-1)
        e = e + 0.5 * params.stiffness * np.minimum(L - params.leg_length, 0.0) ** 2
    return e


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

    state0: np.ndarray
    theta: float
    phi: float
    foot: np.ndarray
    t_touchdown: float
    t_liftoff: float
    t_end: float
    touchdown: np.ndarray
    liftoff: np.ndarray
    state1: np.ndarray
    segments: tuple = field(default=(), repr=False)

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

    def sample(self, t: np.ndarray) -> np.ndarray:
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

    def mirror_error(self) -> np.ndarray:
        """Periodicity defect after the mirror map, shape (4,): (z1 - z0, vx1 - vx0, vy1 + vy0, vz1)."""
        s0, s1 = self.state0, self.state1
        return np.array([s1[2] - s0[2], s1[3] - s0[3], s1[4] + s0[4], s1[5]])


class _Failed(Exception):
    """An event did not occur (the trial gait falls, never lands or never lifts off)."""


def _event(fn, direction: int):
    fn.terminal = True
    fn.direction = direction
    return fn


def simulate_half_cycle(params: SlipParams, state0, theta: float, phi: float, *,
                        dense: bool = False, max_time: float = 3.0) -> HalfCycle:
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
        return _simulate(params, np.asarray(state0, float), theta, phi, dense, max_time)
    except _Failed as exc:
        raise InfeasibleError(f"SLIP half cycle failed: {exc}") from None


def _simulate(params, s0, theta, phi, dense, max_time):
    l0 = params.leg_length
    h_td = l0 * math.cos(theta) * math.cos(phi)
    if not h_td > 0:
        raise _Failed("touchdown height l0 cos(theta) cos(phi) <= 0")
    opts = dict(method=METHOD, rtol=RTOL, atol=ATOL, dense_output=dense)

    # flight until the foot, held at (theta, phi), reaches the ground
    touch = _event(lambda t, s: s[2] - h_td, -1)
    if s0[2] <= h_td:
        raise _Failed(f"TOF height {s0[2]:.4f} m not above the touchdown height {h_td:.4f} m")
    f1 = solve_ivp(flight_rhs(params), (0.0, max_time), s0, events=touch, **opts)
    if f1.status != 1 or not len(f1.t_events[0]):
        raise _Failed("no touchdown")
    t_td = float(f1.t_events[0][0])
    s_td = f1.y_events[0][0]
    foot = s_td[:3] + l0 * leg_direction(theta, phi)
    foot[2] = 0.0

    # stance until the spring is back at rest length (or the mass hits the ground)
    lift = _event(lambda t, s: np.sqrt((s[0] - foot[0]) ** 2 + (s[1] - foot[1]) ** 2 + s[2] ** 2) - l0, 1)
    ground = _event(lambda t, s: s[2], -1)
    st = solve_ivp(stance_rhs(params, foot), (t_td, t_td + max_time), s_td, events=(lift, ground), **opts)
    if st.status != 1 or not len(st.t_events[0]):
        raise _Failed("no lift-off")
    t_lo = float(st.t_events[0][0])
    s_lo = st.y_events[0][0]
    if s_lo[5] <= 0:
        raise _Failed("lift-off while falling (no flight after stance)")

    # flight until the next top of flight
    top = _event(lambda t, s: s[5], -1)
    f2 = solve_ivp(flight_rhs(params), (t_lo, t_lo + max_time), s_lo, events=top, **opts)
    if f2.status != 1 or not len(f2.t_events[0]):
        raise _Failed("no top of flight")
    t_end = float(f2.t_events[0][0])
    s1 = f2.y_events[0][0]
    segs = (f1, st, f2) if dense else ()
    return HalfCycle(s0, float(theta), float(phi), foot, t_td, t_lo, t_end, s_td, s_lo, s1, segs)


@dataclass(frozen=True)
class PeriodicGait:
    """A periodic SLIP half cycle and how it was found.

    Attributes:
        params: SLIP parameters.
        speed: desired forward TOF speed, m/s.
        flight: desired flight time per step tau_F, s; step_width: w, m (foot right of the mid-line).
        half_cycle: the optimised half cycle (dense output), y shifted so the mid-line is y = 0.
        residual: max |residual| at the solution.
        iterations: optimiser iterations (accepted + rejected steps, ``nfev`` of MINPACK lm).
        integrations: half-cycle integrations, finite-difference Jacobians included.
    """

    params: SlipParams
    speed: float
    flight: float
    step_width: float
    half_cycle: HalfCycle
    residual: float
    iterations: int
    integrations: int


def _initial_guess(params: SlipParams, speed: float, flight: float, w: float) -> np.ndarray:
    """(z0, vy0, theta, phi) for the optimiser.

    Vertical impulse over a step: the mean stance force is m g (t_s + t_f) / t_s. For a linear spring
    with a half-sine force profile the peak compression is dl = (pi/2) g (t_s + t_f) / (t_s w0^2),
    w0^2 = k/m, and the stance lasts about pi / w0. The touchdown height l0 - dl/2 ... is a rough
    first guess only; the leg angle follows from the contact length v t_s = 2 l0 sin(angle).
    """
    l0, g = params.leg_length, params.gravity
    w0 = math.sqrt(params.stiffness / params.mass)
    t_s = 0.8 * math.pi / w0
    half = min(0.95, speed * t_s / (2 * l0))
    lean = math.asin(half)
    h = l0 * math.cos(lean)
    z0 = h + 0.125 * g * flight**2
    phi = -math.asin(min(0.5, w / l0))               # foot to the right (-y)
    theta = math.asin(min(max(math.sin(lean) ** 2 - math.sin(phi) ** 2, 0.0), 1.0) ** 0.5)
    vy0 = -w / (t_s + flight) * 0.5
    return np.array([z0, vy0, theta, phi])


def periodic_half_cycle(speed: float = 3.5, *, flight: float = 0.2, step_width: float = 0.1,
                        params: SlipParams | None = None, guess: np.ndarray | None = None,
                        tol: float = 1e-12) -> PeriodicGait:
    """Find the periodic mirror-symmetric half cycle at forward TOF speed ``speed``.

    Args:
        speed: desired forward CoM speed at TOF, m/s (> 0).
        flight: desired flight time per step tau_F (both flight halves), s (> 0).
        step_width: lateral distance w from the running mid-line to the foot, m (>= 0).
        params: SLIP parameters (default :class:`SlipParams`).
        guess: optional start (z0, vy0, theta, phi).
        tol: optimiser tolerance (xtol = ftol = gtol = tol).

    Returns:
        A :class:`PeriodicGait` whose half cycle starts at x = 0 with the mid-line at y = 0.

    Raises:
        InputError: bad arguments. InfeasibleError: no periodic gait found from the start point.
    """
    p = params or SlipParams()
    if not (isinstance(speed, (int, float)) and math.isfinite(speed) and 0 < speed <= 20):
        raise InputError("speed", speed, "a forward TOF speed in (0, 20] m/s")
    if not (isinstance(flight, (int, float)) and math.isfinite(flight) and 0 < flight <= 2):
        raise InputError("flight", flight, "a flight time in (0, 2] s")
    if not (isinstance(step_width, (int, float)) and math.isfinite(step_width)
            and 0 <= step_width < 0.5 * p.leg_length):
        raise InputError("step_width", step_width, f"0 <= w < {0.5 * p.leg_length} m")
    w = step_width
    x0 = _initial_guess(p, speed, flight, w) if guess is None else np.asarray(guess, float)

    count = [0]

    def residual(x: np.ndarray) -> np.ndarray:
        z0, vy0, theta, phi = x
        count[0] += 1
        try:
            hc = _simulate(p, np.array([0.0, 0.0, z0, speed, vy0, 0.0]), theta, phi, False, 3.0)
        except _Failed:
            # a constant penalty: LM treats the trial as a bad step and shrinks its trust region
            return np.full(5, 10.0)
        s0, s1 = hc.state0, hc.state1
        mid = 0.5 * (s0[1] + s1[1])
        return np.array([s1[2] - s0[2], s1[3] - s0[3], s1[4] + s0[4],
                         hc.flight_duration - flight, (hc.foot[1] - mid) + w])

    sol = least_squares(residual, x0, method="lm", xtol=tol, ftol=tol, gtol=tol, max_nfev=2000)
    integrations = count[0]
    res = float(np.max(np.abs(residual(sol.x))))
    if res > 1e-8:
        raise InfeasibleError(
            f"no periodic SLIP half cycle at {speed} m/s with flight {flight} s (residual {res:.1e}) "
            f"for k = {p.stiffness} N/m, m = {p.mass} kg, l0 = {p.leg_length} m, w = {w} m")
    z0, vy0, theta, phi = sol.x
    hc = _simulate(p, np.array([0.0, 0.0, z0, speed, vy0, 0.0]), theta, phi, True, 3.0)
    mid = 0.5 * (hc.state0[1] + hc.state1[1])
    hc = _shift_y(hc, -mid)
    return PeriodicGait(p, float(speed), float(flight), float(w), hc, res, int(sol.nfev), integrations)


def _shift_y(hc: HalfCycle, dy: float) -> HalfCycle:
    """The same half cycle translated by dy in y (dense outputs wrapped)."""
    d = np.array([0.0, dy, 0.0, 0.0, 0.0, 0.0])
    segs = tuple(_Shifted(s, d) for s in hc.segments)
    return replace(hc, state0=hc.state0 + d, foot=hc.foot + d[:3], touchdown=hc.touchdown + d,
                   liftoff=hc.liftoff + d, state1=hc.state1 + d, segments=segs)


class _Shifted:
    """A solve_ivp solution whose dense output is offset by a constant state."""

    def __init__(self, sol, offset: np.ndarray):
        self._sol, self._offset = sol, offset
        self.t = sol.t
        self.y = sol.y + offset[:, None]

    def sol(self, t):
        return self._sol.sol(t) + self._offset[:, None]


def calibrate(speed: float = 3.5, *, flight: float = 0.2, step_width: float = 0.1, height: float = 0.95,
              stance: float = 0.2, mass: float = 80.0, gravity: float = 9.81) -> SlipParams:
    """Leg stiffness k and length l0 whose periodic gait has touchdown height ``height`` and stance
    duration ``stance`` (2-by-2 root solve over (k, l0), each evaluation one gait search).

    The defaults reproduce paper 001 Table I (h = 0.95 m, tau_SS = tau_F = 0.2 s) at the 3.5 m/s of
    §IV-C; :class:`SlipParams` holds the result rounded (see docs/slip.md).

    Raises:
        InfeasibleError: the root solve did not converge.
    """
    from scipy.optimize import root

    def r(x: np.ndarray) -> np.ndarray:
        p = SlipParams(mass=mass, stiffness=float(x[0]) * 1e3, leg_length=float(x[1]), gravity=gravity)
        hc = periodic_half_cycle(speed, flight=flight, step_width=step_width, params=p).half_cycle
        return np.array([hc.touchdown[2] - height, hc.stance_duration - stance])

    sol = root(r, [18.0, height + 0.06], method="hybr", options={"eps": 1e-8})
    if not sol.success or np.max(np.abs(sol.fun)) > 1e-8:
        raise InfeasibleError(f"SLIP calibration failed: {sol.message} (residual {np.max(np.abs(sol.fun)):.1e})")
    return SlipParams(mass=mass, stiffness=float(sol.x[0]) * 1e3, leg_length=float(sol.x[1]), gravity=gravity)
