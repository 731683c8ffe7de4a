"""The truth barrier and the sensed closed loop: the controller side never reads the plant's data (a
run whose plant truth is scrambled between sensing and stepping is bit-identical), the G1 walks on the
estimator with typical noise and runs walk-run-walk on it, heavy noise is taken neither for slip nor
for contact, ten times the noise is clearly worse, the
sole touch sensors read the contact normal force, the floor friction option sets the contact
friction, and the latency pipe delays the torques by exactly L ticks and predicts a
constant-acceleration state exactly."""

from __future__ import annotations

import copy

import mujoco
import numpy as np
import pytest

import gaitshift
from gaitshift.control.prediction import LatencyPredictor
from gaitshift.control.state import DEFAULT_ASSUMED_FRICTION, MAX_BRIDGE
from gaitshift.errors import InputError
from gaitshift.robots.model import standing_qpos
from gaitshift.sim.contacts import ContactSensor
from gaitshift.sim.latency import CommandDelay
from gaitshift.sim.loop import SimOptions, simulate
from gaitshift.sim.plant import build_plant
from gaitshift.sim.sensor_spec import SOLE_TOUCH_SENSORS
from gaitshift.sim.world import with_floor_friction
from loco_checks import short_g1_walk


@pytest.fixture(scope="module")
def walk():
    return gaitshift.plan("g1-walk")


@pytest.fixture(scope="module")
def short_walk():
    """A 1-step walk and its closing step: every contact transition of a walk (stand, lift-off, swing,
    touch-down, stop)."""
    return short_g1_walk(1)


@pytest.fixture(scope="module")
def default_run(walk):
    return simulate(walk)


def _scrambler(model):
    """Hooks: after sensing, save the plant's data and replace it by another robot state (random joints,
    pelvis elsewhere, all derived quantities and the contact list recomputed); after the control,
    restore it except for the command the controller wrote."""
    saved = {}
    rng = np.random.default_rng(1)

    def scramble(k, tp, d):
        saved["d"] = copy.copy(d)
        mujoco.mj_resetData(model, d)
        d.qpos[:3] = (1.0, -2.0, 0.3)
        d.qpos[7:] = rng.uniform(-0.5, 0.5, model.nq - 7)
        d.qvel[:] = rng.normal(0.0, 3.0, model.nv)
        mujoco.mj_forward(model, d)
        mujoco.mj_subtreeVel(model, d)

    def restore(k, tp, d):
        ctrl, push = d.ctrl.copy(), d.xfrc_applied.copy()
        mujoco.mj_copyData(d, model, saved["d"])
        d.ctrl[:], d.xfrc_applied[:] = ctrl, push

    return scramble, restore


@pytest.mark.parametrize("state", ["estimated", "oracle"])
def test_scrambling_the_plant_truth_after_sensing_gives_a_bit_identical_run(short_walk, state):
    plant = build_plant()
    scramble, restore = _scrambler(plant.model)
    opts = SimOptions(state=state, latency=2)
    ref = simulate(short_walk, opts, plant=plant)
    run = simulate(short_walk, opts, plant=plant, hooks=[restore], sense_hooks=[scramble])
    assert not ref.fell
    for key in ("qpos", "qvel", "tau", "est_qpos", "est_contact"):
        assert np.array_equal(ref.arrays[key], run.arrays[key]), key


def test_the_g1_walks_on_the_estimator_with_typical_noise(default_run):
    met = default_run.metrics
    assert not default_run.fell, met.get("fall_reason")
    assert met["steps_completed"] == met["steps_planned"]
    assert met["state_source"] == "estimated"
    est = met["estimation"]
    assert est["used_by_controller"]
    assert est["base_vel_rmse"] <= 0.05
    assert est["tilt_rmse"] <= 0.02
    assert est["contact_accuracy"] >= 0.95
    assert est["pos_drift_per_m"] <= 0.05


def _touchdowns(a: dict) -> np.ndarray:
    """(n, 2): for each true touch-down (a sole's first tick with a normal force after >= 20 ticks
    without), the ticks from it to the controller's stance flag for that sole (the foot scheduler's,
    ``stance``), and how far, m, the true sole centre was then above its height at the touch-down."""
    loaded, stance, z = a["contact"] & (a["grf"][:, :, 2] > 0), a["stance"], a["foot_pos"][:, :, 2]
    rows = []
    for s in (0, 1):
        edges = np.flatnonzero(np.diff(loaded[:, s].astype(int)) == 1) + 1
        for k in edges[edges >= 20]:
            if loaded[k - 20 : k, s].any() or stance[k - 20, s]:
                continue
            off = k - 20 + np.flatnonzero(~stance[k - 20 : k + 1, s])[-1]  # the scheduler's swing before it
            on = np.flatnonzero(stance[off:, s])
            flag = off + on[0] if len(on) else len(stance) - 1
            rows.append((flag - k if len(on) else len(stance), z[flag, s] - z[k, s]))
    return np.array(rows)


def test_the_controller_takes_a_foot_for_landed_when_it_touches_the_floor(default_run):
    """Walking feet touch the floor about 15 ticks before the plan's touch-down (a heel grazing with a
    few newtons); the scheduler takes a swing foot for landed when the estimator sees a landing (the
    sole back at the ground level while the other stands), not only once the force from the motors'
    torques crosses its threshold. Against the truth's touch-downs, on torque contact (g1-walk, seed
    0): median 16 ticks late with the force trigger alone."""
    delays = _touchdowns(default_run.arrays)[:, 0]
    assert len(delays) >= 10
    assert abs(np.median(delays)) <= 2 and np.percentile(delays, 90) <= 6, delays


def test_with_latency_the_torques_still_read_measured_accelerations(walk):
    """With 4 ticks of latency the controller acts on a state predicted with its own planned
    accelerations; the torque window must take the estimated state before that prediction, or eq. (2) of
    torque_contact.py gives back what the QP assumed. It did: every touch-down of g1-walk was taken 13-95
    ticks early, the sole 6-38 mm above the floor (seed 0); in the check below, median 16 ticks early and
    3 of 11 touch-downs countable. A sole that hovers its last millimetres may be taken for landed a few
    ticks early; the check is on the height (seed 0: up to 14 ticks early with the sole 2.2 mm above its
    touch-down height)."""
    run = simulate(walk, SimOptions(latency=4))
    found = _touchdowns(run.arrays)
    assert len(found) >= 10
    assert abs(np.median(found[:, 0])) <= 2 and np.max(found[:, 1]) <= 0.003, found


def test_the_g1_runs_walk_run_walk_on_the_estimator_by_default():
    """The issue's acceptance run: the default options (estimated state, typical noise) carry the G1
    through walking, running and back with every step done, and the estimator meets its targets; its
    contact is off within a tick of every take-off into a flight."""
    run = simulate(gaitshift.plan("g1-walk-run-walk"))
    met = run.metrics
    assert not run.fell, met.get("fall_reason")
    assert met["steps_completed"] == met["steps_planned"]
    assert met["flight_ratio"] >= 0.7  # it really runs: 70 % of the planned flight (issue 5)
    assert met["state_source"] == "estimated"
    est = met["estimation"]
    assert est["base_vel_rmse"] <= 0.05
    assert est["tilt_rmse"] <= 0.01
    # the IMU sees each take-off (contact_fusion.py, "Flight"): no sole is on a tick into a flight (>= 5 ticks);
    # from the motors' torques alone the lifting sole stayed on for 6-9 ticks
    a = run.arrays
    flight = ~(a["contact"] & (a["grf"][:, :, 2] > 0.0)).any(axis=1)
    starts = [k for k in np.flatnonzero(~flight[:-1] & flight[1:]) + 1 if flight[k : k + 5].all()]
    assert len(starts) >= 8
    assert not [round(float(a["t"][k]), 3) for k in starts if a["est_contact"][k + 1].any()]


def test_heavy_sensor_noise_is_not_taken_for_slip_or_for_contact(walk):
    """``rl-peer`` noise (joint velocities +-1.5 rad/s, angles +-0.01 rad) on a floor of friction 1: no
    sole slips, so no slip is flagged and the friction the controller assumes stays where it started
    (slip.py eq. (4) sets the slip threshold above the noise), and the sole forces from the torques keep
    the contact right 90 % of the time (the window and thresholds of torque_contact.py eq. (3)). With the
    thresholds of ``typical`` noise: 51 slip ticks, the friction assumed down to 0.1 and 88.7 % contact
    accuracy (g1-walk, seed 0)."""
    run = simulate(walk, SimOptions(noise="rl-peer"))
    est = run.metrics["estimation"]
    assert not run.fell, run.metrics.get("fall_reason")
    assert est["slip_ticks"] == 0
    assert est["friction_assumed_final"] == pytest.approx(DEFAULT_ASSUMED_FRICTION)
    assert est["contact_accuracy"] >= 0.90


def test_ten_times_the_noise_gives_clearly_larger_estimation_errors(walk, default_run):
    noisy = simulate(walk, SimOptions(noise_scale=10.0))
    e1, e10 = default_run.metrics["estimation"], noisy.metrics["estimation"]
    assert e10["base_vel_rmse"] > 2 * e1["base_vel_rmse"]
    assert e10["tilt_rmse"] > 2 * e1["tilt_rmse"]


def test_oracle_runs_report_the_estimator_alongside(short_walk):
    met = simulate(short_walk, SimOptions(state="oracle", noise="none")).metrics
    assert met["state_source"] == "oracle"
    assert met["estimation"]["used_by_controller"] is False
    assert met["estimation"]["tilt_rmse"] < 0.01


def test_sole_touch_sensors_read_the_contact_normal_force():
    plant = build_plant()
    m = plant.model
    d = mujoco.MjData(m)
    d.qpos[:] = standing_qpos(plant)
    d.qpos[2] -= 0.001
    for _ in range(5):
        mujoco.mj_step(m, d)
    mujoco.mj_forward(m, d)
    touch = np.array([d.sensordata[m.sensor(n).adr[0]] for n in SOLE_TOUCH_SENSORS])
    grf = ContactSensor(plant).read(d).grf
    assert np.all(touch > 10.0)
    np.testing.assert_allclose(touch, grf[:, 2], rtol=1e-6)


def test_the_floor_friction_option_sets_the_contact_friction():
    plant = build_plant()
    slippery = with_floor_friction(plant, 0.3)
    assert slippery.model is not plant.model  # the cached plant is not touched
    d = mujoco.MjData(slippery.model)
    d.qpos[:] = standing_qpos(slippery)
    d.qpos[2] -= 0.001
    mujoco.mj_forward(slippery.model, d)
    assert d.ncon > 0
    assert all(d.contact[i].friction[0] == pytest.approx(0.3) for i in range(d.ncon))


def test_the_latency_pipe_delays_torques_by_l_ticks_and_predicts_constant_acceleration():
    m = build_plant().model
    pipe, predictor = CommandDelay(3), LatencyPredictor(m, 3, MAX_BRIDGE)
    out = [pipe.send(np.full(m.nu, float(k))) for k in range(6)]
    assert [o[0] for o in out] == [0.0, 0.0, 0.0, 0.0, 1.0, 2.0]  # starts full of the first command
    for _ in range(6):
        predictor.sent(np.ones(m.nv))
    q0 = standing_qpos(build_plant())
    v0 = np.zeros(m.nv)
    q, v = predictor.predict(q0, v0)  # three pending commands with qdd = 1
    np.testing.assert_allclose(v, 3 * m.opt.timestep * np.ones(m.nv))
    dt = m.opt.timestep
    np.testing.assert_allclose(q[7:] - q0[7:], dt * dt * (1 + 2 + 3) * np.ones(m.nq - 7))


@pytest.mark.parametrize(
    ("key", "value"),
    [
        ("state", "truth"),
        ("noise", "loud"),
        ("noise_scale", -1.0),
        ("latency", 51),
        ("friction", 0.0),
        ("seed", -1),
        ("known_floor", "yes"),
    ],
)
def test_bad_sensing_options_name_the_field(key, value):
    with pytest.raises(InputError) as info:
        SimOptions(**{key: value})
    assert info.value.field == key
