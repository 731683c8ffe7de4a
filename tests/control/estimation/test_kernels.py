"""The compiled tick (numba kernels) computes what the Python path computes.

* MuJoCo's quaternion routines re-implemented in the kernels (integrate, to and from a matrix) agree
  with MuJoCo's own on random inputs to 1 ulp (MuJoCo's build fuses some products into FMAs);
* on random force, height, speed and plan sequences around the thresholds, the kernels of the force
  trigger, the fused contact and the slip low-pass give the flags (and ground level, low-passed
  rates, centre speeds) of :class:`ContactDetector`, :class:`ContactFusion` and :class:`SlipDetector`;
* on the recorded G1 sway with a sole pushed across a slippery floor (slip flags set, the support
  test run), with and without the plan's flags, for both InEKF variants and both force windows, every
  field of every :class:`EstimatedState` of the compiled path equals the Python path's to 1e-11
  (the flags exactly): the force trigger, the joint filter, the kinematics, the mean step, the
  correction ticks, the slip test and the fused contact all follow the same equations;
* the compiled path is used where it covers the set-up and not for leg odometry.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from gaitshift.bench.g1sway import record_g1_sway
from gaitshift.control.estimation import ContactDetector, StateEstimator, kernels
from gaitshift.control.estimation.contact_fusion import (
    CUSUM_THRESHOLD,
    LAND_SPEED,
    LIFT_HEIGHT,
    SWING_SPEED,
    ContactFusion,
)
from gaitshift.control.estimation.slip import SlipDetector
from gaitshift.robots import load_robot

FIELDS = ("base_pos", "base_quat", "base_vel", "base_omega", "q", "qd", "foot_vel", "com", "com_vel")
FLAGS = ("contact", "stance", "slip")


@pytest.fixture(scope="module")
def g1():
    return load_robot("g1")


@pytest.fixture(scope="module")
def pushed(g1):
    return record_g1_sway(g1, duration=3.0, profile="typical", seed=2, slippery=0, push=(2.0, 2.4, 40.0))


def test_quaternion_routines_match_mujoco():
    rng = np.random.default_rng(0)
    ulp = 2.3e-16
    for scale in (0.0, 1e-3, 1.0, 30.0):
        for _ in range(200):
            quat = rng.normal(size=4)
            quat /= np.linalg.norm(quat)
            w = rng.normal(size=3) * scale
            ours, theirs = quat.copy(), quat.copy()
            kernels.quat_integrate(ours, w, 0.002)
            mujoco.mju_quatIntegrate(theirs, w, 0.002)
            np.testing.assert_allclose(ours, theirs, rtol=0, atol=2 * ulp)
            mat_ours, mat_theirs = np.empty(9), np.empty(9)
            kernels.quat_to_mat(mat_ours, theirs)
            mujoco.mju_quat2Mat(mat_theirs, theirs)
            np.testing.assert_allclose(mat_ours, mat_theirs, rtol=0, atol=2 * ulp)
            q_ours, q_theirs = np.empty(4), np.empty(4)
            kernels.mat_to_quat(q_ours, mat_theirs)
            mujoco.mju_mat2Quat(q_theirs, mat_theirs)
            np.testing.assert_allclose(q_ours, q_theirs, rtol=0, atol=2 * ulp)


@pytest.mark.parametrize(("window", "debounce", "with_plan"), [(1, 1, True), (2, 1, False), (3, 2, True)])
def test_contact_kernels_equal_the_classes(window, debounce, with_plan):
    rng = np.random.default_rng(window)
    on, off, std = 10.0, 4.0, 2.0
    det = ContactDetector(100.0, on / 100.0, off / 100.0, debounce, window)
    fusion = ContactFusion(on, off, std, window)
    ist, fst = np.zeros(kernels.IST_SIZE, np.int64), np.zeros(kernels.FST_SIZE)
    fst[kernels.F_GROUND] = np.nan
    fst[kernels.F_STAND : kernels.F_STAND + 2] = np.nan
    recent, means = np.zeros((2, window)), np.zeros(2)
    rules = [CUSUM_THRESHOLD, LIFT_HEIGHT, SWING_SPEED, LAND_SPEED, fusion.flight_on, fusion.flight_off]
    par = np.array([on, off, fusion.cusum_gain, fusion.cusum_half, fusion.near, fusion.still, *rules])
    fired = landed = flights = airborne = 0
    a_v = 9.81
    for _ in range(4000):
        normal = rng.uniform(-3.0, 14.0, 2)
        heights = rng.uniform(-1.5e-3, 3.0e-3, 2)  # in and out of the ground band (0.8 mm), and lifted (2 mm)
        vel = np.zeros((2, 3))
        vel[:, 2] = vz = rng.uniform(-0.4, 0.08, 2)  # down to faster than a landing (0.3 m/s)
        vel[:, 0] = rng.uniform(0.0, 1.3, 2)  # below and above the swing speed (1 m/s)
        speed = np.array([math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2) for v in vel])
        planned = rng.random(2) < 0.7 if with_plan else None
        flags = det.update_values(normal.tolist())
        det.release(fusion.veto)
        flags = (flags[0] and not fusion.veto[0], flags[1] and not fusion.veto[1])
        a_v = float(np.clip(a_v + rng.normal(0.0, 2.0), -6.0, 12.0))  # a random walk through flights and stances
        fused = fusion.update_values(normal.tolist(), heights.tolist(), vz.tolist(), planned, speed.tolist(), a_v)
        kernels.force_means(normal, recent, ist, means)
        kernels.force_trigger(means, det.on_force, det.off_force, debounce, ist)  # the veto's release included
        plan = -1 if planned is None else int(planned[0]) | int(planned[1]) << 1
        kernels.fuse_contact(normal, means, heights, vel, plan, par, ist, fst, a_v)
        assert tuple(ist[kernels.I_STANCE : kernels.I_STANCE + 2]) == flags
        assert tuple(ist[kernels.I_FUSED : kernels.I_FUSED + 2]) == tuple(fused)
        assert fst[kernels.F_GROUND] == pytest.approx(
            fusion.ground if fusion.ground is not None else np.nan, nan_ok=True
        )
        assert ist[kernels.I_FLIGHT] == int(fusion.flight)
        assert tuple(ist[kernels.I_AIRBORNE : kernels.I_AIRBORNE + 2]) == tuple(fusion.airborne)
        flights += int(fusion.flight)
        airborne += int(any(fusion.airborne))
        fired += int(fused[0] != flags[0])
        landed += int(ist[kernels.I_LAND] + ist[kernels.I_LAND + 1])
    assert fired > 100  # the fused flags do depart from the force trigger's: the height and plan rules ran
    assert landed > 100  # and so did the landing rule
    assert flights > 100 and airborne > 100  # and the flight rule


def test_slip_lowpass_equals_the_detector():
    rng = np.random.default_rng(5)
    nj, dt, lim = 4, 0.002, 0.2
    det = SlipDetector(dt, lim, 0.03)
    ist, fst = np.zeros(kernels.IST_SIZE, np.int64), np.zeros(kernels.FST_SIZE)
    rates_lp, xv = np.zeros((2, 3 + nj)), np.zeros((8, 3))
    moved = 0
    for _ in range(3000):
        stance = rng.random(2) < 0.9
        xv[4:6] = rng.normal(0.15, 0.2, (2, 3))
        omega, qd = rng.normal(size=3), rng.normal(size=nj)
        det.update((bool(stance[0]), bool(stance[1])), xv[4:6], np.concatenate((omega, qd)), _no_twist)
        need = kernels.slip_lowpass(stance.astype(np.int64), xv, omega, qd, det.alpha, lim, fst, ist, rates_lp)
        assert tuple(ist[kernels.I_MOVING : kernels.I_MOVING + 2]) == det.moving
        for i in (0, 1):
            np.testing.assert_allclose(rates_lp[i], det.rates_lp[i], rtol=0, atol=1e-14)
            assert bool(need & kernels.SUPPORT << i) == (stance[i] and fst[kernels.F_SPEED + i] > lim)
        moved += int(any(det.moving))
    assert moved > 100


def _no_twist(i, rates):
    return np.zeros(3), np.eye(3)


def _run(g1, run, compiled, **kwargs):
    est = StateEstimator.from_robot(g1, run.dt, noise="typical", compiled=compiled, **kwargs)
    assert est.compiled == compiled
    est.reset(run.qpos0, run.qvel0)
    plans = [np.array([True, k % 50 < 40]) for k in range(len(run.imu))]  # a swing every 0.1 s for the plan rules
    return [est.step(run.imu[k], run.joints[k], run.forces[k], plans[k]) for k in range(len(run.imu))]


@pytest.mark.parametrize(("name", "window"), [("inekf", 2), ("inekf-flat", 1)])
def test_compiled_tick_equals_the_python_path(g1, pushed, name, window):
    python = _run(g1, pushed, False, filter=name, contact_window=window, debounce=1)
    compiled = _run(g1, pushed, True, filter=name, contact_window=window, debounce=1)
    assert sum(bool(s.slip.any()) for s in python) > 50  # the push does make the support test flag a slip
    for a, b in zip(python, compiled, strict=True):
        for field in FIELDS:
            np.testing.assert_allclose(getattr(b, field), getattr(a, field), rtol=0, atol=1e-11, err_msg=field)
        for field in FLAGS:
            np.testing.assert_array_equal(getattr(b, field), getattr(a, field), err_msg=field)
        assert b.cov_trace == pytest.approx(a.cov_trace, rel=1e-12, abs=1e-15)


def test_no_plan_and_default_contact_settings_agree(g1, pushed):
    est = {c: StateEstimator.from_robot(g1, pushed.dt, filter="inekf", compiled=c) for c in (False, True)}
    for e in est.values():
        e.reset(pushed.qpos0, pushed.qvel0)
    for k in range(len(pushed.imu)):
        a, b = (e.step(pushed.imu[k], pushed.joints[k], pushed.forces[k]) for e in est.values())
        np.testing.assert_allclose(b.base_vel, a.base_vel, rtol=0, atol=1e-11)
        np.testing.assert_array_equal(b.contact, a.contact)
        np.testing.assert_array_equal(b.stance, a.stance)


def test_leg_odometry_keeps_the_python_path(g1):
    assert not StateEstimator.from_robot(g1, 0.002, filter="leg-odometry").compiled
    assert StateEstimator.from_robot(g1, 0.002).compiled
