"""The slip test tells a pivot from a slide: a rigid sole turning about a point of its support is not
slipping (its centre moves), a sole whose every support point moves is; eq. (2) of the slip module is the
distance from the origin to the velocity image of the support polygon."""

from __future__ import annotations

import numpy as np
import pytest

from gaitshift.common.hull import convex_hull_xy
from gaitshift.control.estimation.joints import JointVelocityFilter
from gaitshift.control.estimation.slip import (
    SlipDetector,
    distance_to_polygon,
    lowpass_rate_variance,
    still_speed_sigma,
)

DT, SPEED, TAU = 0.002, 0.2, 0.03
#: a G1-like sole: contact points (sole frame, relative to the centre), m
SOLE = np.array([[-0.085, 0.025, 0.0], [-0.085, -0.025, 0.0], [0.085, 0.03, 0.0], [0.085, -0.03, 0.0]])


def _run(vel: np.ndarray, omega: np.ndarray, ticks: int = 300) -> SlipDetector:
    """Left sole in stance for ``ticks`` with a constant twist (centre velocity, angular velocity)."""
    det = SlipDetector(DT, SPEED, TAU, (SOLE, SOLE))
    v = np.stack([vel, np.zeros(3)])
    for _ in range(ticks):
        det.update((True, False), v, omega, _twist)
    return det


def _twist(i: int, rates: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The rates are the sole's world angular velocity; the sole is level."""
    return rates, np.eye(3)


@pytest.mark.parametrize("pivot", [0, 2, 3])
def test_a_yaw_pivot_about_a_support_point_is_no_slip(pivot: int) -> None:
    omega = np.array([0.0, 0.0, 6.7])  # rad/s, the yaw rate seen at a G1 push-off
    vel = np.cross(omega, -SOLE[pivot])  # centre velocity of a body turning about that point
    det = _run(vel, omega)
    assert np.hypot(*vel[:2]) > 2 * SPEED  # the centre test alone would flag it
    assert det.slip == (False, False)
    assert det.moving == (True, False)  # but the centre is no still point for the base filter
    assert det.speed[0] == pytest.approx(0.0, abs=1e-9)


def test_a_slide_moves_every_point_and_is_flagged() -> None:
    omega = np.array([0.0, 0.0, 2.0])
    slide = np.array([0.5, 0.0, 0.0])
    det = _run(np.cross(omega, -SOLE[2]) + slide, omega)
    assert det.slip == (True, False)
    # the slowest support point moves at 0.5 m/s less at most the turn over the sole (2 rad/s x 0.17 m)
    assert 0.5 - 2.0 * 0.18 < det.speed[0] <= 0.5 + 1e-9


def test_pure_translation_speed_is_the_centre_speed() -> None:
    det = _run(np.array([0.24, -0.18, 0.0]), np.zeros(3))
    assert det.speed[0] == pytest.approx(0.3, rel=1e-3)
    assert det.slip == (True, False)


def test_swing_resets_and_no_support_gives_the_centre_rule() -> None:
    det = SlipDetector(DT, SPEED, TAU)  # no support polygon: the centre only
    z, w = np.zeros((2, 3)), np.array([0.0, 0.0, 6.7])
    v = np.array([[0.6, 0.0, 0.0], [0.0, 0.0, 0.0]])
    for _ in range(300):
        det.update((True, True), v, w, _twist)
    assert det.slip == (True, False)
    det.update((False, True), v, w, _twist)
    assert det.slip == (False, False) and det.vel_lp[0] == [0.0, 0.0]
    det.update((False, False), z, w, _twist)
    assert det.moving == (False, False)


def test_distance_to_polygon_identities() -> None:
    square = convex_hull_xy(np.array([[1.0, 1, 0], [-1, 1, 0], [1, -1, 0], [-1, -1, 0], [0, 0, 0]]))
    assert len(square) == 4  # the interior point is dropped
    assert distance_to_polygon(square[:, :2]) == 0.0
    assert distance_to_polygon(square[:, :2] + [3.0, 0.0]) == pytest.approx(2.0)
    assert distance_to_polygon(square[::-1, :2] + [3.0, 4.0]) == pytest.approx(np.hypot(2.0, 3.0))
    assert distance_to_polygon(np.array([[3.0, 4.0]])) == pytest.approx(5.0)
    assert distance_to_polygon(np.array([[3.0, 4.0]] * 4)) == pytest.approx(5.0)  # a degenerate image


def test_eq4_is_the_spread_of_a_still_soles_low_passed_velocity() -> None:
    """Monte Carlo of the noise path of eq. (4): white encoder and driver readings of a still joint
    through the joint filter, the sole velocity ``J qd + w x r`` with a white gyro, the detector's low-pass.
    The low-passed velocity's std per axis and the Rayleigh sigma match eq. (4) within 5 %."""
    rng = np.random.default_rng(0)
    nj, ticks = 6, 40_000
    pos_std, vel_std, gyro_std = 0.0058, 0.87, 0.115
    jf = JointVelocityFilter(nj, DT, pos_std, vel_std, 100.0)
    jac = rng.uniform(-0.4, 0.4, (2, 3, nj))
    lever = np.array([[0.0, 0.1, -0.7], [0.02, -0.1, -0.7]])
    det = SlipDetector(DT, 1e9, TAU)  # never slips: only its low-pass is read
    jf.reset(np.zeros(nj))
    lp = np.zeros((ticks, 2, 2))
    for k in range(ticks):
        _, qd = jf.update(rng.normal(0.0, pos_std, nj), rng.normal(0.0, vel_std, nj))
        w = rng.normal(0.0, gyro_std, 3)
        vel = jac @ qd + np.cross(w, lever)
        det.update((True, True), vel, np.zeros(1), _twist)
        lp[k] = det.vel_lp
    lp = lp[2000:]
    rate_var = lowpass_rate_variance(jf.a, jf.gain, np.diag([pos_std**2, vel_std**2]), det.alpha)
    g = det.alpha / (2 - det.alpha) * gyro_std**2
    for i in (0, 1):
        rx, ry, rz = lever[i]
        sx = np.sqrt(rate_var * jac[i, 0] @ jac[i, 0] + g * (ry**2 + rz**2))
        sy = np.sqrt(rate_var * jac[i, 1] @ jac[i, 1] + g * (rx**2 + rz**2))
        assert lp[:, i].std(axis=0) == pytest.approx([sx, sy], rel=0.05)
    sigma = np.sqrt((lp**2).mean(axis=(0, 2)))  # per sole, the Rayleigh parameter sqrt((sx^2 + sy^2) / 2)
    assert still_speed_sigma(jac, lever, rate_var, gyro_std**2, det.alpha) == pytest.approx(sigma.max(), rel=0.05)
