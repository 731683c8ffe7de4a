"""Slip of a stance sole: a rigid sole slides only when no point of its support is still.

The sole is rigid. Its world twist (``v_c``, m/s, velocity of the sole centre ``c``; ``w``, rad/s)
gives every point ``p`` of the sole the velocity (rigid-body kinematics)::

    v(p) = v_c + w x (p - c)                                                    (1)

The test low-passes the twist (first order, time constant ``tau`` s, reset in swing), so zero-mean
noise of the joint velocities averages out and a sustained motion does not, and evaluates (1) with
the low-passed twist over the sole's support polygon ``P`` (the convex hull of its contact points,
read from the model, e.g. the four sphere bottoms of the G1)::

    s = min_{p in P} | LP(v_c) + LP(w) x (p - c) |_xy          (m/s)            (2)
    slip = stance and s > slip_speed                                            (3)

The horizontal velocity is affine in ``p``, so the image of ``P`` is a convex polygon in the velocity
plane and ``s`` is the distance from the origin to it: ``s = 0`` when the instantaneous centre of
rotation lies within the support (a heel swinging about the toe, a sole rolling off its toe edge:
a pivot, the contact point is still), while a slide moves every point (``s`` is then the speed of the
slowest one). A sole without a support polygon (one point, its centre) gets the centre test
``|LP(v_c)|_xy > slip_speed``. If both stance soles exceed the threshold, only the one with the larger
``s`` slips: a sliding sole biases the estimated base velocity, which makes the still sole look as if
it moved.

The detector also flags a stance sole whose *centre* moves, ``|LP(v_c)|_xy > slip_speed`` (the same
rule on the centre alone, the faster sole when both): a pivoting sole is not sliding, but its centre,
the point the base filter takes as still, is not a still point either (:attr:`SlipDetector.moving`).

What the test cannot see: a sole spinning flat about a point of its support slides everywhere but
there (torsional slip); it is counted as still.

The threshold keeps above the test's own noise. A still sole's low-passed velocity is not zero: the
sensors' noise reaches it through the joint-velocity filter (per joint, ``x_{k+1} = A x_k + K z_k``,
``x = [q, qd]``, readings ``z`` of covariance ``R_z``: :class:`~gaitshift.control.estimation.joints.
JointVelocityFilter`), the low-pass ``y_{k+1} = (1 - a) y_k + a qd_{k+1}`` and the leg's Jacobian
``J`` (sole centre, base frame), and through the gyro's white noise ``sigma_g`` times the lever ``r``
from the IMU to the sole. The stacked system ``s = [q, qd, y]`` has the stationary covariance of the
discrete Lyapunov equation ``S = F S F^T + G R_z G^T``, so per horizontal axis ``u``::

    sigma_u^2 = S_yy sum_j J_uj^2 + a / (2 - a) sigma_g^2 |e_u x r|^2                     (4)

and the centre speed of a still sole is Rayleigh-distributed with ``sigma = sqrt((sigma_x^2 +
sigma_y^2) / 2)`` (the larger sole's), ``P(s > k sigma) = exp(-k^2 / 2)``. The test slips at
``max(slip_speed, NOISE_SIGMAS sigma)`` (:func:`still_speed_sigma`). On the G1 (eq. (4) at the standing and
at the straight-leg pose; measured on stance ticks of g1-walk, seed 0): ``typical`` noise, sigma
0.008-0.009 m/s, the measured median speed 0.008 m/s (a Rayleigh median is 1.18 sigma), its largest 0.053
m/s: the 0.2 m/s threshold stands; ``rl-peer`` noise (joint velocities +-1.5 rad/s), sigma 0.067-0.077
m/s, the measured median 0.078 m/s, its largest 0.247 m/s, above 0.2 m/s: every false onset lowered the
friction the controller assumes by a fifth, to 0.1 within 1.9 s of g1-walk-run-walk (docs/estimation.md,
"Heavy sensor noise").
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from scipy.linalg import solve_discrete_lyapunov

from gaitshift.common.hull import convex_hull_xy

#: multiples of the still sole's speed noise sigma (eq. (4)) the slip threshold keeps above: a Rayleigh
#: tail of exp(-12.5) = 3.7e-6 per sample, about 330 independent samples (tau apart) per sole in a 10-s walk
NOISE_SIGMAS = 5.0


def lowpass_factor(dt: float, tau: float) -> float:
    """The factor ``a`` of the first-order low-pass ``y <- y + a (x - y)`` of time constant ``tau`` s
    sampled every ``dt`` s: ``1 - exp(-dt / tau)``."""
    return float(1.0 - np.exp(-dt / tau))


def lowpass_rate_variance(transition: np.ndarray, gain: np.ndarray, reading_cov: np.ndarray, alpha: float) -> float:
    """``S_yy`` of eq. (4): the stationary variance, (rad/s)^2, of one joint's low-passed filtered
    velocity, from the joint filter's transition ``A`` (2, 2) and gain ``K`` (2, 2), the readings'
    covariance ``R_z`` (2, 2) and the low-pass factor ``alpha``."""
    f = np.zeros((3, 3))
    f[:2, :2] = transition
    f[2, :2] = alpha * transition[1]
    f[2, 2] = 1.0 - alpha
    g = np.zeros((3, 2))
    g[:2] = gain
    g[2] = alpha * gain[1]
    return float(solve_discrete_lyapunov(f, g @ reading_cov @ g.T)[2, 2])


def still_speed_sigma(jac: np.ndarray, lever: np.ndarray, rate_var: float, gyro_var: float, alpha: float) -> float:
    """``sigma`` (m/s) of eq. (4), the larger sole's: ``jac`` (2, 3, nj) the soles' translational
    Jacobians on the joints, ``lever`` (2, 3) m the soles from the IMU (base frame), ``rate_var`` the
    low-passed joint-velocity variance ``S_yy`` (rad/s)^2, ``gyro_var`` the gyro's per-sample variance
    (rad/s)^2, ``alpha`` the low-pass factor."""
    g = alpha / (2.0 - alpha) * gyro_var
    out = 0.0
    for j, (rx, ry, rz) in zip(jac, lever, strict=True):
        var_x = rate_var * float(j[0] @ j[0]) + g * (ry * ry + rz * rz)
        var_y = rate_var * float(j[1] @ j[1]) + g * (rx * rx + rz * rz)
        out = max(out, ((var_x + var_y) / 2.0) ** 0.5)
    return out


def distance_to_polygon(u: Any) -> float:
    """Distance (same unit as ``u``) from the origin to the convex polygon with vertices ``u`` (k, 2) in
    order (either sense; k = 1 or 2 give a point or a segment): 0 inside. Plain floats: k is a handful."""
    pts = u.tolist() if isinstance(u, np.ndarray) else u
    k = len(pts)
    best2, sides = float("inf"), set()
    for j in range(k):
        ax, ay = pts[j]
        bx, by = pts[(j + 1) % k]
        ex, ey = bx - ax, by - ay
        cross = ex * ay - ey * ax  # e x (0 - a), sign flipped: one sign on every edge when inside
        sides.add(cross > 0.0 if cross != 0.0 else None)
        ee = ex * ex + ey * ey
        t = 0.0 if ee <= 0.0 else min(1.0, max(0.0, -(ax * ex + ay * ey) / ee))
        px, py = ax + t * ex, ay + t * ey
        best2 = min(best2, px * px + py * py)
    if k >= 3 and len(sides) == 1 and None not in sides:
        return 0.0
    return float(best2**0.5)


class SlipDetector:
    """Slip flags of the two soles from their world twists (module docstring, eqs. (1)-(3)).

    The angular velocity of a sole is linear in a rate vector (for the estimator: the IMU rate and the
    joint velocities), ``w = W rates`` with ``W`` (the rotation and the Jacobian) varying little over
    ``tau``; the detector low-passes the rates (per sole, reset in swing) and asks for ``LP(w) = W
    LP(rates)`` only when the centre test fires, so most ticks cost two low-pass updates.

    Args:
        dt: tick period, s.
        slip_speed: speed of the slowest support point above which a stance sole slips, m/s (the
            caller keeps it above the noise: :func:`still_speed_sigma`).
        slip_tau: time constant of the low-pass on the twist, s.
        supports: (left, right) contact points (n, 3) in the sole frame relative to the sole centre,
            m; None: the centre only.
    """

    def __init__(
        self,
        dt: float,
        slip_speed: float,
        slip_tau: float,
        supports: tuple[np.ndarray, np.ndarray] | None = None,
    ) -> None:
        self.slip_speed = float(slip_speed)
        self.alpha = lowpass_factor(dt, slip_tau)
        zero = np.zeros((1, 3))
        self.supports = tuple(convex_hull_xy(s) for s in supports) if supports is not None else (zero, zero)
        self.reset()

    def reset(self) -> None:
        """Forget the low-passed twists (both soles as in swing) and the flags."""
        self.vel_lp = [[0.0, 0.0], [0.0, 0.0]]  # sole-centre horizontal velocity, world, m/s
        self.rates_lp: list[Any] = [0.0, 0.0]  # low-passed rate vectors (0 in swing)
        self.speed = [0.0, 0.0]  # s of eq. (2), m/s
        self.slip = (False, False)
        self.moving = (False, False)

    def support_speed(self, i: int, vx: float, vy: float, omega: np.ndarray, rot: np.ndarray) -> float:
        """``s`` of eq. (2) for sole ``i``: low-passed centre velocity ``(vx, vy)`` m/s, angular velocity
        ``omega`` (3,) rad/s and rotation sole -> world ``rot`` (3, 3)."""
        wx, wy, wz = omega.tolist()
        r = self.supports[i].dot(rot.T).tolist()  # support vertices relative to the centre, world, m
        return distance_to_polygon([(vx + wy * z - wz * y, vy + wz * x - wx * z) for x, y, z in r])  # eq. (1)

    @staticmethod
    def resolve(flags: list[bool], speed: list[float]) -> tuple[bool, bool]:
        """The slip flags (2,) from the per-sole tests: when both fire, the faster sole alone (a slide
        biases the base velocity, so the still sole looks slow-moving too)."""
        if flags[0] and flags[1]:
            return speed[0] >= speed[1], speed[1] > speed[0]
        return flags[0], flags[1]

    def update(
        self,
        stance: tuple[bool, bool],
        vel: Any,
        rates: np.ndarray,
        twist: Callable[[int, np.ndarray], tuple[np.ndarray, np.ndarray]],
    ) -> tuple[bool, bool]:
        """One tick: ``stance`` (2,) flags, sole-centre velocities ``vel`` (2, 3) m/s (an array, or its
        rows as lists), the rate vector
        ``rates`` (k,) and ``twist(i, LP(rates))`` -> (angular velocity (3,) rad/s, rotation sole -> world
        (3, 3)) of sole ``i``, called only for a sole whose centre moves."""
        a, lim = self.alpha, self.slip_speed
        flags = [False, False]
        centre = [0.0, 0.0]
        rows = vel.tolist() if isinstance(vel, np.ndarray) else vel
        for i in (0, 1):
            lp = self.vel_lp[i]
            if not stance[i]:
                lp[0] = lp[1] = 0.0
                self.rates_lp[i] = 0.0
                self.speed[i] = 0.0
                continue
            vx, vy = rows[i][0], rows[i][1]
            lp[0] += a * (vx - lp[0])
            lp[1] += a * (vy - lp[1])
            self.rates_lp[i] = self.rates_lp[i] + a * (rates - self.rates_lp[i])
            centre[i] = self.speed[i] = (lp[0] * lp[0] + lp[1] * lp[1]) ** 0.5
            if centre[i] <= lim:  # the centre lies in the support: s <= |LP(v_c)|_xy
                continue
            omega, rot = twist(i, self.rates_lp[i])
            self.speed[i] = self.support_speed(i, lp[0], lp[1], omega, rot)
            flags[i] = self.speed[i] > lim
        self.slip = self.resolve(flags, self.speed)
        moving = [centre[0] > lim, centre[1] > lim]
        if moving[0] and moving[1]:
            moving = [centre[0] >= centre[1], centre[1] > centre[0]]
        self.moving = (moving[0], moving[1])
        return self.slip
