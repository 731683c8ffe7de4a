"""The phase maps of eqs. (3)-(6) match an independent integration of eq. (1), and the periodic
orbits of the steady gaits are periodic: integrating eq. (1) with solve_ivp over two steps from the
orbit state with its foot pattern returns to the same state relative to the stance foot (rotated by
the turn of two steps when turning)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from gaitshift.models.stiffness import stiffness
from gaitshift.planners.locomotion.affine import phase_matrix
from gaitshift.planners.locomotion.orbit import Orbit
from gaitshift.planners.locomotion.steps import Anchor, Timing, build_step_types

H, G = 0.6333, 9.81
TM = Timing(0.327, 0.122, 0.327, 0.122, 0.654, 0.816)
TYPES = build_step_types(stiffness(H, TM.run_single, TM.double, TM.flight, G), TM, H, G)


def _integrate_phase(kind, T, tau, x0, v0, c0, c1):
    """One phase of eq. (1) (horizontal, per axis, ZMP linear from c0 to c1), by solve_ivp."""
    if kind == 2:
        return x0 + v0 * tau, v0
    rhs = lambda t, y: [y[1], (y[0] - (c0 + (c1 - c0) * t / tau)) / T**2]  # noqa: E731
    sol = solve_ivp(rhs, (0, tau), [x0, v0], rtol=1e-12, atol=1e-13)
    return sol.y[0, -1], sol.y[1, -1]


@pytest.mark.parametrize("name", list(TYPES))
def test_phase_matrices_match_an_integration_of_eq1(name):
    for ph in TYPES[name].phases:
        M = phase_matrix(ph.kind, ph.stiffness, ph.duration)
        for x0, v0, c0, c1 in ((0.1, 0.4, 0.0, 0.2), (-0.05, -0.3, 0.1, -0.1)):
            ref = _integrate_phase(ph.kind, ph.stiffness, ph.duration, x0, v0, c0, c1)
            got = M @ np.array([x0, v0, c0, c1])
            assert np.allclose(got, ref, atol=1e-9), (name, ph)


def _two_steps(step, S, feet):
    """Integrate two steps from the 4-state S (x, y, vx, vy) with ZMP anchors at the given feet."""
    x, v = S[:2].copy(), S[2:].copy()
    for k in range(2):
        for ph in step.phases:
            ends = (
                []
                if ph.zmp is None
                else [feet[k] if a == Anchor.OWN else feet[k + 1] for a in (ph.zmp.start, ph.zmp.end)]
            )
            for ax in range(2):
                c0, c1 = (ends[0][ax], ends[1][ax]) if ends else (0.0, 0.0)
                x[ax], v[ax] = _integrate_phase(ph.kind, ph.stiffness, ph.duration, x[ax], v[ax], c0, c1)
    return x, v


@pytest.mark.parametrize("name", ["walk", "run"])
@pytest.mark.parametrize(
    ("speed", "yaw_rate"), [((0.6, 0.0), 0.0), ((0.9, 0.1), 0.0), ((0.7, 0.0), 0.5), ((0.5, -0.05), -0.4)]
)
def test_orbits_are_periodic_over_two_steps(name, speed, yaw_rate):
    step = TYPES[name]
    orb = Orbit.of(step)
    w = 0.237
    rho, nu = orb.state(speed, w, 0, yaw_rate)  # left stance, in its own frame (yaw 0)
    dL, dR = orb.pattern(speed, w, yaw_rate)
    th = yaw_rate * step.duration
    R = lambda a: np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])  # noqa: E731
    f0 = np.zeros(2)
    f1 = f0 + R(th) @ dL
    f2 = f1 + R(2 * th) @ dR
    x, v = _two_steps(step, np.r_[rho, nu], [f0, f1, f2])
    assert np.allclose(R(-2 * th) @ (x - f2), rho, atol=1e-9)
    assert np.allclose(R(-2 * th) @ v, nu, atol=1e-9)
