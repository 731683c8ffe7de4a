"""Periodic 3D-SLIP gait search and leg calibration (paper 001 §IV-C, after Wensing & Orin).

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

The dynamics and the half-cycle integration are in :mod:`gaitshift.models.slip.dynamics`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import least_squares

from gaitshift.errors import InfeasibleError, InputError
from gaitshift.models.arrays import FloatArray
from gaitshift.models.slip.dynamics import (
    DenseSegment,
    HalfCycle,
    HalfCycleFailed,
    SlipParams,
    integrate_half_cycle,
)


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


def _initial_guess(params: SlipParams, speed: float, flight: float, w: float) -> FloatArray:
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
    phi = -math.asin(min(0.5, w / l0))  # foot to the right (-y)
    theta = math.asin(min(max(math.sin(lean) ** 2 - math.sin(phi) ** 2, 0.0), 1.0) ** 0.5)
    vy0 = -w / (t_s + flight) * 0.5
    return np.array([z0, vy0, theta, phi])


def periodic_half_cycle(
    speed: float = 3.5,
    *,
    flight: float = 0.2,
    step_width: float = 0.1,
    params: SlipParams | None = None,
    guess: FloatArray | None = None,
    tol: float = 1e-12,
) -> PeriodicGait:
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
    if not (
        isinstance(step_width, (int, float)) and math.isfinite(step_width) and 0 <= step_width < 0.5 * p.leg_length
    ):
        raise InputError("step_width", step_width, f"0 <= w < {0.5 * p.leg_length} m")
    w = step_width
    x0 = _initial_guess(p, speed, flight, w) if guess is None else np.asarray(guess, float)

    count = [0]

    def residual(x: FloatArray) -> FloatArray:
        z0, vy0, theta, phi = x
        count[0] += 1
        try:
            hc = integrate_half_cycle(p, np.array([0.0, 0.0, z0, speed, vy0, 0.0]), theta, phi, False, 3.0)
        except HalfCycleFailed:
            # a constant penalty: LM treats the trial as a bad step and shrinks its trust region
            return np.full(5, 10.0)
        s0, s1 = hc.state0, hc.state1
        mid = 0.5 * (s0[1] + s1[1])
        return np.array(
            [s1[2] - s0[2], s1[3] - s0[3], s1[4] + s0[4], hc.flight_duration - flight, (hc.foot[1] - mid) + w]
        )

    sol = least_squares(residual, x0, method="lm", xtol=tol, ftol=tol, gtol=tol, max_nfev=2000)
    integrations = count[0]
    res = float(np.max(np.abs(residual(sol.x))))
    if res > 1e-8:
        raise InfeasibleError(
            f"no periodic SLIP half cycle at {speed} m/s with flight {flight} s (residual {res:.1e}) "
            f"for k = {p.stiffness} N/m, m = {p.mass} kg, l0 = {p.leg_length} m, w = {w} m"
        )
    z0, vy0, theta, phi = sol.x
    hc = integrate_half_cycle(p, np.array([0.0, 0.0, z0, speed, vy0, 0.0]), theta, phi, True, 3.0)
    mid = 0.5 * (hc.state0[1] + hc.state1[1])
    hc = _shift_y(hc, -mid)
    return PeriodicGait(p, float(speed), float(flight), float(w), hc, res, int(sol.nfev), integrations)


def _shift_y(hc: HalfCycle, dy: float) -> HalfCycle:
    """The same half cycle translated by dy in y (dense outputs wrapped)."""
    d = np.array([0.0, dy, 0.0, 0.0, 0.0, 0.0])
    segs = tuple(_Shifted(s, d) for s in hc.segments)
    return replace(
        hc,
        state0=hc.state0 + d,
        foot=hc.foot + d[:3],
        touchdown=hc.touchdown + d,
        liftoff=hc.liftoff + d,
        state1=hc.state1 + d,
        segments=segs,
    )


class _Shifted:
    """A solve_ivp solution whose dense output is offset by a constant state."""

    def __init__(self, sol: DenseSegment, offset: FloatArray):
        self._sol, self._offset = sol, offset
        self.t = sol.t
        self.y = sol.y + offset[:, None]

    def sol(self, t: FloatArray) -> FloatArray:
        return self._sol.sol(t) + self._offset[:, None]


def calibrate(
    speed: float = 3.5,
    *,
    flight: float = 0.2,
    step_width: float = 0.1,
    height: float = 0.95,
    stance: float = 0.2,
    mass: float = 80.0,
    gravity: float = 9.81,
) -> SlipParams:
    """Leg stiffness k and length l0 whose periodic gait has touchdown height ``height`` and stance
    duration ``stance`` (2-by-2 root solve over (k, l0), each evaluation one gait search).

    The defaults reproduce paper 001 Table I (h = 0.95 m, tau_SS = tau_F = 0.2 s) at the 3.5 m/s of
    §IV-C; :class:`SlipParams` holds the result rounded (see docs/slip.md).

    Raises:
        InfeasibleError: the root solve did not converge.
    """
    from scipy.optimize import root

    def r(x: FloatArray) -> FloatArray:
        p = SlipParams(mass=mass, stiffness=float(x[0]) * 1e3, leg_length=float(x[1]), gravity=gravity)
        hc = periodic_half_cycle(speed, flight=flight, step_width=step_width, params=p).half_cycle
        return np.array([hc.touchdown[2] - height, hc.stance_duration - stance])

    sol = root(r, [18.0, height + 0.06], method="hybr", options={"eps": 1e-8})
    if not sol.success or np.max(np.abs(sol.fun)) > 1e-8:
        raise InfeasibleError(f"SLIP calibration failed: {sol.message} (residual {np.max(np.abs(sol.fun)):.1e})")
    return SlipParams(mass=mass, stiffness=float(sol.x[0]) * 1e3, leg_length=float(sol.x[1]), gravity=gravity)
