"""Kinematic limits of the step adjustment (issue 13, point 1): the reach of eq. (1) of
:mod:`gaitshift.control.step_limits` from the G1's model (Pythagoras on the leg), the reach disc and
the crossing guard of a clamped foothold, and a swing foot that re-targets mid-swing as the measured
capture point moves, inside those limits, until the freeze point."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from gaitshift.control.feedback import CaptureSettings, PlanShift, SwingContext
from gaitshift.control.step_limits import StepLimits
from gaitshift.sim.plant import build_plant


@pytest.fixture(scope="module")
def g1():
    return build_plant()


def test_reach_is_the_horizontal_leg_at_the_planned_hip_height(g1):
    """r^2 + z_hip^2 = (rho L)^2 with z_hip = h - (CoM - hip axis height when standing)."""
    m, robot = g1.model, g1.robot
    d = mujoco.MjData(m)
    d.qpos[:] = robot.standing_qpos(m)
    mujoco.mj_forward(m, d)
    drop = d.subtree_com[0][2] - np.mean([d.xanchor[m.joint(h).id][2] for h in robot.hips])
    for h, rho in ((0.62, 0.95), (0.55, 1.0)):
        lim = StepLimits.from_plant(g1, h, rho)
        assert lim.reach**2 + (h - drop) ** 2 == pytest.approx((rho * robot.leg_length) ** 2, rel=1e-9)
    lim = StepLimits.from_plant(g1, 0.62, 0.95)
    assert lim.min_width == robot.sole_size[1]
    assert 0.5 * robot.foot_separation > lim.hip_offset > 0  # the hips are inside the feet when standing
    assert StepLimits.from_plant(g1, 0.55, 0.95).reach > lim.reach  # lower hips reach further


def test_clamp_keeps_a_foothold_in_the_reach_disc_and_off_the_other_foot():
    lim = StepLimits(reach=0.3, hip_offset=0.06, min_width=0.07)
    com = np.array([1.0, 0.0, 0.6])
    yaw = math.pi / 2  # heading +y: the robot's left is -x
    far = lim.clamp(0, np.array([1.0, 2.0, 0.0]), com, yaw, other=np.array([1.2, 0.0, 0.0]))
    hip = np.array([1.0 - 0.06, 0.0])
    assert np.linalg.norm(far[:2] - hip) == pytest.approx(0.3)
    # a left foot aimed right of the right foot goes back to min_width on its left (-x here)
    crossing = lim.clamp(0, np.array([1.1, 0.1, 0.0]), com, yaw, other=np.array([1.0, 0.1, 0.0]))
    np.testing.assert_allclose(crossing, [1.0 - 0.07, 0.1, 0.0], atol=1e-12)
    inside = np.array([0.95, 0.05, 0.0])
    np.testing.assert_array_equal(lim.clamp(0, inside, com, yaw, other=np.array([1.2, 0.0, 0.0])), inside)


def test_a_swing_foot_re_targets_mid_swing_inside_the_limits_until_the_freeze_point():
    lim = StepLimits(reach=0.25, hip_offset=0.06, min_width=0.07)
    shift = PlanShift(CaptureSettings(), omega=4.0, limits=lim)
    footholds = np.array([[0.3, 0.12, 0.0], [0.0, -0.12, 0.0]])  # left swings to (0.3, 0.12)
    ctx = SwingContext(footholds, footholds.copy(), np.array([0.2, 0.0]), 0.0)
    stance = np.array([False, True])
    com, ref, zero = np.array([0.1, 0.0, 0.6]), np.array([0.1, 0.0, 0.6]), np.zeros(3)
    seen = []
    for u, vy in ((0.2, 0.2), (0.4, 0.6), (0.5, 4.0), (0.6, -1.6), (0.8, 3.0)):
        shift.correct_swings(stance, np.array([u, 0.0]), com, np.array([0.0, vy, 0.0]), ref, zero, ctx)
        seen.append(shift.offset[0].copy())
    assert seen[0][1] == pytest.approx(0.2 / 4.0)  # gain 1: the capture-point error, inside the limits
    assert seen[1][1] == pytest.approx(0.6 / 4.0)  # re-targeted mid-swing
    # pushed hard left: 1 m asked, the foot stops on the reach circle around the predicted left hip
    hip = com[:2] + 0.2 * np.array([0.0, 4.0]) + [0.0, 0.06]
    assert np.linalg.norm(footholds[0, :2] + seen[2][:2] - hip) == pytest.approx(0.25)
    assert 0.0 < seen[2][1] < 4.0 / 4.0
    # pushed right: the left foot would cross the right one; it stops min_width left of it
    assert footholds[0, 1] + seen[3][1] == pytest.approx(-0.12 + 0.07)
    np.testing.assert_array_equal(seen[4], seen[3])  # frozen after u = 0.7
    off = PlanShift(CaptureSettings(kinematic_limits=False), omega=4.0, limits=lim)
    off.correct_swings(stance, np.array([0.6, 0.0]), com, np.array([0.0, -1.6, 0.0]), ref, zero, ctx)
    assert off.offset[0][1] == pytest.approx(-1.6 / 4.0)  # without the limits: the raw correction


def test_the_correction_is_the_error_predicted_at_touchdown_on_the_other_foots_stance():
    """delta = k (xi - xi_ref) exp(omega tau), tau = min(time to touchdown, stance time left of the
    other foot); 0 when the other foot is in the air."""
    omega = 4.0
    footholds = np.array([[0.3, 0.12, 0.0], [0.0, -0.12, 0.0]])
    com, zero = np.array([0.1, 0.0, 0.6]), np.zeros(3)
    vel = np.array([0.0, 0.2, 0.0])  # capture-point error 0.05 m to the left
    for stance_left, stance_r, tau in ((0.1, True, 0.1), (0.5, True, 0.2), (0.5, False, 0.0)):
        ctx = SwingContext(footholds, footholds.copy(), np.array([0.2, 0.0]), 0.0, np.array([0.0, stance_left]))
        shift = PlanShift(CaptureSettings(kinematic_limits=False), omega=omega)
        shift.correct_swings(np.array([False, stance_r]), np.array([0.3, 0.0]), com, vel, com, zero, ctx)
        assert shift.offset[0][1] == pytest.approx(0.05 * math.exp(omega * tau)), (stance_left, stance_r)
    plain = PlanShift(CaptureSettings(kinematic_limits=False, predict_touchdown=False), omega=omega)
    plain.correct_swings(np.array([False, True]), np.array([0.3, 0.0]), com, vel, com, zero, ctx)
    assert plain.offset[0][1] == pytest.approx(0.05)


def test_a_foothold_a_short_step_from_the_other_foot_may_line_up_with_it_but_never_cross_it():
    """Eq. (2): l_min = w max(clip((L + c - |a|) / c), clip((|a| - 2L - c) / c)): in line allowed for
    L + c <= |a| <= 2L + c, the sole width side by side and on long steps; continuous in a."""
    w, length, c = 0.07, 0.18, 0.01
    lim = StepLimits(reach=1.0, hip_offset=0.06, min_width=w, sole_length=length, clearance=c)
    com, right = np.array([0.1, 0.0, 0.6]), np.array([0.0, -0.12, 0.0])
    # asked 0.18 m across the right foot, a short step (0.2 m) ahead of it: in line, a tandem step
    ahead = lim.clamp(0, np.array([0.2, -0.3, 0.0]), com, 0.0, right)
    np.testing.assert_allclose(ahead, [0.2, -0.12, 0.0], atol=1e-12)
    # the same ask side by side, or a long step (0.5 m) ahead: the sole width
    beside = lim.clamp(0, np.array([0.05, -0.3, 0.0]), com, 0.0, right)
    np.testing.assert_allclose(beside, [0.05, -0.12 + w, 0.0], atol=1e-12)
    far = lim.clamp(0, np.array([0.5, -0.3, 0.0]), com, 0.0, right)
    np.testing.assert_allclose(far, [0.5, -0.12 + w, 0.0], atol=1e-12)
    for a in (0.0, 0.18, -0.18, 0.38, -0.5):
        assert lim.min_gap(a) == w
    for a in (0.19, -0.19, 0.3, -0.365):
        assert lim.min_gap(a) == pytest.approx(0.0, abs=1e-12)
    assert lim.min_gap(0.185) == pytest.approx(0.5 * w) and lim.min_gap(0.375) == pytest.approx(0.5 * w)
    gaps = np.array([lim.min_gap(a) for a in np.linspace(-0.6, 0.6, 1201)])
    assert np.max(np.abs(np.diff(gaps))) <= w * 0.001 / c + 1e-12  # continuous: slope w / c
    # the clamped distance never decreases as the ask moves to the foot's own side
    out = [lim.clamp(0, np.array([0.3, -0.12 + dl, 0.0]), com, 0.0, right)[1] for dl in np.linspace(-0.3, 0.3, 601)]
    assert np.all(np.diff(out) >= -1e-12)
    # c = None (from_plant) and the bare limits keep the sole width at any distance
    assert StepLimits(reach=1.0, hip_offset=0.06, min_width=w).min_gap(0.3) == w


def test_the_tandem_limits_come_from_the_robot_sole(g1):
    lim = StepLimits.from_plant(g1, 0.62, 0.95, clearance=0.01)
    length, width = g1.robot.sole_size
    assert (lim.sole_length, lim.min_width) == (length, width)
    assert lim.min_gap(length + 0.01) == pytest.approx(0.0, abs=1e-12)
    assert lim.min_gap(2 * length + 0.005) == pytest.approx(0.0, abs=1e-12)
    assert lim.min_gap(2 * length + 0.02) == width
    assert StepLimits.from_plant(g1, 0.62, 0.95).min_gap(0.3) == width
