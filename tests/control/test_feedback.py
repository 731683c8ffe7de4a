"""Capture-point step feedback: the foothold correction formula and the plan-shift state.

The correction is recomputed here from its definition, delta = k (xi - xi_ref) with xi = c + cd /
omega, clipped per axis; the shift's first-order lag is compared with its closed form
target (1 - (1 - dt / T)^n) after n ticks.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from gaitshift.control.feedback import (
    CaptureSettings,
    PlanShift,
    SwingContext,
    capture_point_offset,
    dcm_error_after,
    heading_gain,
    predicted_error,
)


def test_offset_is_the_gain_times_the_capture_point_error_clipped_per_axis():
    omega = np.sqrt(9.81 / 0.6)
    com, vel = np.array([0.10, -0.02, 0.60]), np.array([0.50, 0.10, -0.3])
    com_ref, vel_ref = np.array([0.08, 0.00, 0.62]), np.array([0.45, 0.00, 0.0])
    out = capture_point_offset(com, vel, com_ref, vel_ref, omega, 0.8, 1.0)
    xi = com[:2] + vel[:2] / omega
    xi_ref = com_ref[:2] + vel_ref[:2] / omega
    np.testing.assert_allclose(out, [*(0.8 * (xi - xi_ref)), 0.0], atol=1e-15)
    clipped = capture_point_offset(com + np.array([1.0, -1.0, 0.0]), vel, com_ref, vel_ref, omega, 1.0, 0.1)
    np.testing.assert_array_equal(clipped, [0.1, -0.1, 0.0])


@pytest.mark.parametrize("yaw", [0.0, 0.7, -2.5])
def test_a_lateral_gain_above_one_turns_the_divergent_component_back_across_the_heading(yaw):
    """The foothold moved by diag(k, k_y) of the error in the heading frame (k_y on the part beyond the
    sole's lateral CoP room, none here; k alone on a running step); on that stance the LIPM's
    divergent component obeys xi' = omega (xi - p), so an error e0 becomes
    e(t) = k e0 + (1 - k) e0 exp(omega t) per heading axis: held for k = 1 (along the heading), and
    back to zero at t* = ln(k / (k - 1)) / omega for k > 1 (across). Integrated here, any heading."""
    omega, k_y = np.sqrt(9.81 / 0.62), 1.3
    rot = np.array([[np.cos(yaw), -np.sin(yaw)], [np.sin(yaw), np.cos(yaw)]])
    e0 = rot @ np.array([0.03, 0.05])  # m: along and across the heading
    settings = CaptureSettings(gain=1.0, lateral_gain=k_y)
    p = heading_gain(e0, settings, yaw)  # the foothold's offset from the plan's
    dt, t_star = 1e-5, np.log(k_y / (k_y - 1.0)) / omega
    e = e0.copy()
    for _ in range(round(t_star / dt)):
        e = e + dt * omega * (e - p)
    along, across = rot.T @ e
    assert along == pytest.approx(0.03, abs=1e-9)
    assert abs(across) < 1e-4 * 0.05 * np.exp(omega * t_star)
    np.testing.assert_allclose(heading_gain(e0, CaptureSettings(gain=0.8, lateral_gain=None), yaw), 0.8 * e0)
    room = 0.035  # the sole's half width: the lateral gain acts only beyond it, and not on a running step
    np.testing.assert_allclose(heading_gain(rot @ [0.0, 0.02], settings, yaw, True, room), rot @ [0.0, 0.02])
    beyond = heading_gain(rot @ [0.0, -0.05], settings, yaw, True, room)
    np.testing.assert_allclose(beyond, rot @ [0.0, -0.05 - (k_y - 1.0) * 0.015], atol=1e-15)
    np.testing.assert_allclose(heading_gain(e0, settings, yaw, False), e0)


def test_landing_moves_the_foot_correction_into_the_plan_shift_target():
    shift = PlanShift(CaptureSettings(), omega=4.0)
    shift.offset[:] = [[0.02, -0.01, 0.0], [0.03, 0.04, 0.0]]
    shift.land(np.array([False, True]))
    np.testing.assert_array_equal(shift.target, [0.03, 0.04, 0.0])
    np.testing.assert_array_equal(shift.offset, [[0.02, -0.01, 0.0], [0.0, 0.0, 0.0]])
    shift.land(np.array([True, False]))
    np.testing.assert_allclose(shift.target, [0.05, 0.03, 0.0])


def test_shift_follows_its_target_with_a_first_order_lag():
    settings = CaptureSettings(shift_time=0.1)
    shift = PlanShift(settings, omega=4.0)
    shift.target[:] = [0.05, -0.02, 0.0]
    dt, n = 0.002, 60
    for _ in range(n):
        shift.blend(dt)
    np.testing.assert_allclose(shift.shift, shift.target * (1 - (1 - dt / 0.1) ** n), rtol=1e-12)
    for _ in range(2000):
        shift.blend(dt)
    np.testing.assert_allclose(shift.shift, shift.target, atol=1e-12)


@pytest.mark.parametrize(("gain", "updated"), [(1.0, [True, False]), (0.0, [False, False])])
def test_only_swinging_feet_before_the_freeze_point_are_corrected(gain, updated):
    """Foot 0 swings at u = 0.5 (corrected unless the gain is 0), foot 1 at u = 0.8 > freeze_u (frozen);
    stance feet are never corrected."""
    shift = PlanShift(CaptureSettings(gain=gain, freeze_u=0.7), omega=4.0)
    shift.target[:] = [0.01, 0.0, 0.0]
    com, vel = np.array([0.2, 0.05, 0.6]), np.array([0.3, 0.0, 0.0])
    plan_com, plan_vel = np.array([0.15, 0.0, 0.6]), np.array([0.3, 0.0, 0.0])
    shift.correct_swings(np.array([False, False]), np.array([0.5, 0.8]), com, vel, plan_com, plan_vel)
    expected = capture_point_offset(com, vel, plan_com + shift.target, plan_vel, 4.0, gain, 0.1)
    got = [bool(np.any(shift.offset[s] != 0.0)) for s in (0, 1)]
    assert got == updated
    if updated[0]:
        np.testing.assert_array_equal(shift.offset[0], expected)
    shift.offset[:] = 0.0
    shift.correct_swings(np.array([True, True]), np.array([0.1, 0.1]), com, vel, plan_com, plan_vel)
    assert np.all(shift.offset == 0.0)


def test_anchoring_sets_the_shift_to_the_mean_offset_of_the_stance_soles_and_holds_it_in_flight():
    """Target = mean over the stance soles of (measured - planned), height included; the swinging
    sole is ignored; with no sole in stance (flight) the target is held; ``anchor`` False leaves it."""
    shift = PlanShift(CaptureSettings(), omega=4.0)
    shift.target[2] = 0.01
    measured = np.array([[1.02, 0.11, 0.004], [0.70, -0.05, 0.09]])
    planned = np.array([[1.00, 0.10, 0.0], [0.65, -0.10, 0.0]])
    shift.anchor_on(np.array([True, False]), measured, planned)
    np.testing.assert_allclose(shift.target, [0.02, 0.01, 0.004], atol=1e-15)
    shift.anchor_on(np.array([True, True]), measured, planned)
    np.testing.assert_allclose(shift.target, [0.035, 0.03, 0.047], atol=1e-15)
    shift.anchor_on(np.array([False, False]), measured + 1.0, planned)
    np.testing.assert_allclose(shift.target, [0.035, 0.03, 0.047], atol=1e-15)
    off = PlanShift(CaptureSettings(anchor=False), omega=4.0)
    off.anchor_on(np.array([True, True]), measured, planned)
    assert np.all(off.target == 0.0)


def test_predicted_error_is_the_lipm_divergent_component_with_the_cop_at_the_sole_edge():
    """e' = omega (e - d sign e) per axis of the sole frame (the CoP held at the edge of a sole of half
    sizes d until the error is taken back, then on it), integrated with small explicit Euler steps,
    against predicted_error's closed form; d = 0 gives the plain exp(omega tau)."""
    omega, tau, yaw = 4.0, 0.2, 0.4
    room = np.array([0.085, 0.025])
    rot = np.array([[np.cos(yaw), -np.sin(yaw)], [np.sin(yaw), np.cos(yaw)]])
    local = np.array([[0.12, -0.04], [-0.05, 0.01], [0.2, 0.026]])  # beyond, inside, just beyond the sole
    e, n = local.copy(), 20_000
    for _ in range(n):
        moved = e + (tau / n) * omega * (e - room * np.sign(e))
        e = np.where(np.sign(moved) == np.sign(e), moved, 0.0)
    assert e[1, 1] == 0.0 and abs(e[1, 0]) < 0.05 and abs(e[0, 0]) > 0.12  # taken back, in part, grown
    for k in range(len(local)):
        got = predicted_error(rot @ local[k], np.exp(omega * tau), room, yaw)
        np.testing.assert_allclose(got, rot @ e[k], atol=1e-5)
    plain = predicted_error(np.array([0.03, -0.01]), np.exp(omega * tau), np.zeros(2), yaw)
    np.testing.assert_allclose(plain, np.array([0.03, -0.01]) * np.exp(omega * tau), rtol=1e-12)


def test_an_error_the_stance_sole_can_take_back_moves_no_foothold():
    """A capture-point error of 1 cm to the left, 0.2 s before the touchdown, with the other foot in
    stance: inside the sole's half width (2.5 cm) no correction; without cop_room 1 cm exp(omega tau)."""
    omega = 4.0
    footholds = np.array([[0.3, 0.12, 0.0], [0.0, -0.12, 0.0]])
    com, zero, vel = np.array([0.1, 0.0, 0.6]), np.zeros(3), np.array([0.0, 0.04, 0.0])
    ctx = SwingContext(footholds, footholds.copy(), np.array([0.2, 0.0]), 0.0, np.array([0.0, 0.5]))
    room, plain = (0.085, 0.025), CaptureSettings(kinematic_limits=False)
    with_room = PlanShift(replace(plain, cop_room=True), omega=omega, room=room)
    without = PlanShift(replace(plain, cop_room=False), omega=omega, room=room)
    for shift in (with_room, without):
        shift.correct_swings(np.array([False, True]), np.array([0.3, 0.0]), com, vel, com, zero, ctx)
    np.testing.assert_array_equal(with_room.offset[0], [0.0, 0.0, 0.0])
    assert without.offset[0][1] == pytest.approx(0.01 * np.exp(omega * 0.2))


def test_dcm_error_after_is_the_lipm_divergent_component_with_the_cop_held_at_an_offset():
    """e' = omega (e - c) per heading axis with the CoP held at the offset c, integrated with small
    explicit Euler steps and stopped at 0, against dcm_error_after's closed form: an offset on the
    error's side takes it back (to 0 when large enough), one on the other side makes it grow faster
    than exp(omega tau), and c = 0 is the plain exp(omega tau)."""
    omega, tau, yaw = 4.0, 0.25, -0.7
    rot = np.array([[np.cos(yaw), -np.sin(yaw)], [np.sin(yaw), np.cos(yaw)]])
    local = np.array([[0.05, -0.03], [0.02, 0.01], [-0.04, 0.0]])
    cops = np.array([[0.02, 0.015], [0.05, -0.01], [0.0, 0.02]])
    e, n = local.copy(), 20_000
    for _ in range(n):
        moved = e + (tau / n) * omega * (e - cops)
        e = np.where(np.sign(moved) == np.sign(e), moved, 0.0)
    g = np.exp(omega * tau)
    assert e[1, 0] == 0.0 and abs(e[0, 1]) > 0.03 * g and 0 < e[0, 0] < 0.05 * g  # back to 0, faster, slower
    for k in range(len(local)):
        got = dcm_error_after(rot @ local[k], g, rot @ cops[k], yaw)
        np.testing.assert_allclose(got, rot @ e[k], atol=1e-5)
    np.testing.assert_allclose(dcm_error_after(rot @ local[0], g, np.zeros(2), yaw), rot @ local[0] * g, rtol=1e-12)


def test_the_commanded_cop_is_what_the_touchdown_prediction_leaves_to_the_stance_sole():
    """With ``commanded_cop`` the swinging foot's correction is dcm_error_after with the CoP offset the
    controller reports for the stance sole, as far as it lies on the error's side (an offset on the
    other side counts as 0); with the setting off it is the plain k (xi - xi_ref) exp(omega tau)."""
    omega, tau = 4.0, 0.2
    footholds = np.array([[0.3, 0.12, 0.0], [0.0, -0.12, 0.0]])
    com, zero, vel = np.array([0.1, 0.0, 0.6]), np.zeros(3), np.array([0.02, 0.04, 0.0])
    cop = np.array([0.004, 0.006])
    seen = []

    def reported(side):
        seen.append(side)
        return cop

    ctx = SwingContext(footholds, footholds.copy(), np.array([tau, 0.0]), 0.0, np.array([0.0, 0.5]), None, reported)
    on = PlanShift(CaptureSettings(kinematic_limits=False), omega=omega)
    off = PlanShift(CaptureSettings(kinematic_limits=False, commanded_cop=False), omega=omega)
    for shift in (on, off):
        shift.correct_swings(np.array([False, True]), np.array([0.3, 0.0]), com, vel, com, zero, ctx)
    err = vel[:2] / omega
    np.testing.assert_allclose(on.offset[0][:2], dcm_error_after(err, np.exp(omega * tau), cop, 0.0), atol=1e-15)
    np.testing.assert_allclose(off.offset[0][:2], err * np.exp(omega * tau), atol=1e-15)
    assert seen == [1]  # asked for the stance sole's CoP, once
    cop[0] = -0.004  # behind the sole centre while the error is ahead: not taking it back
    on.correct_swings(np.array([False, True]), np.array([0.3, 0.0]), com, vel, com, zero, ctx)
    g = np.exp(omega * tau)
    np.testing.assert_allclose(on.offset[0][:2], [err[0] * g, err[1] * g - cop[1] * (g - 1)], atol=1e-15)
