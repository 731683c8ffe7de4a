"""Perturbations as options of ``simulate`` and ``SimOptions`` (issue 13, point 4): pushes of any
direction and timing, bumps on the floor of the plant only, extra joint-velocity sensor noise, and the
scenario's ``sim:`` block; each with a check that can fail."""

from __future__ import annotations

import math
from types import SimpleNamespace

import mujoco
import numpy as np
import pytest

from gaitshift.control.controller import Controller
from gaitshift.control.estimation.noise import noise_profile
from gaitshift.errors import InputError
from gaitshift.robots.model import standing_qpos
from gaitshift.scenario.sim_settings import SimSettings
from gaitshift.sim.bumps import Bump, parse_bump
from gaitshift.sim.contacts import ContactSensor
from gaitshift.sim.loop import SimOptions
from gaitshift.sim.perturb import with_joint_vel_noise
from gaitshift.sim.plant import build_plant
from gaitshift.sim.pushes import Push, parse_push, push_forces
from gaitshift.sim.sensors import SensorModel


def test_a_push_of_any_direction_and_timing_delivers_its_impulse_vector():
    p = parse_push("1.5,3,-4,12,0.2")
    assert isinstance(p, Push) and p.t == 1.5 and p.duration == 0.2
    assert p.impulse == pytest.approx(13.0)  # |(3, -4, 12)|
    dt = 0.002
    f = push_forces((p,), 0.25, dt, 2000)
    np.testing.assert_allclose(f.sum(axis=0) * dt, [3.0, -4.0, 12.0], atol=1e-9)
    on = np.flatnonzero(np.any(f != 0, axis=1))
    assert on[0] == round((1.5 + 0.25) / dt) and len(on) == round(0.2 / dt)
    assert parse_push("12") == 12.0  # the legacy lateral form
    q = parse_push("0,0,5")  # default duration, horizontal
    assert isinstance(q, Push) and q.duration == 0.1 and q.direction == (0.0, 1.0, 0.0)


@pytest.mark.parametrize("bad", ["", "x", "1,2", "-1,2,3", "1,2,3,4,0", "1,2,3,4,5,6", "-3", "nan", "1,2000,0"])
def test_a_bad_push_is_one_input_error_naming_the_flag(bad):
    with pytest.raises(InputError, match="--push"):
        parse_push(bad)


def test_a_bump_is_a_box_on_the_plants_floor_that_the_feet_stand_on():
    bump = Bump(x=-0.3, height=0.05, length=0.6)  # under both feet of the standing robot
    plant = build_plant(bumps=(bump,))
    m = plant.model
    g = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, "bump0")
    assert g >= 0 and m.geom_bodyid[g] == 0 and m.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX
    np.testing.assert_allclose(m.geom_pos[g], [0.0, 0.0, 0.025])
    assert mujoco.mj_name2id(build_plant().model, mujoco.mjtObj.mjOBJ_GEOM, "bump0") < 0  # nominal: none
    d = mujoco.MjData(m)
    d.qpos[:] = standing_qpos(plant)
    d.qpos[2] += 0.05 - 1e-4  # the soles 0.1 mm into the bump's top face
    mujoco.mj_forward(m, d)
    contacts = ContactSensor(plant).read(d)
    assert contacts.touching.all() and contacts.foreign is None
    # the controller's model has no bump, and its copy never collides: it is not told about the bump
    ctrl = Controller.from_scenario("g1-walk")
    assert mujoco.mj_name2id(ctrl.robot.model, mujoco.mjtObj.mjOBJ_GEOM, "bump0") < 0
    assert ctrl.state.cmodel.opt.disableflags & int(mujoco.mjtDisableBit.mjDSBL_CONTACT)


@pytest.mark.parametrize("bad", ["1", "1,0", "1,0.6", "1,0.05,0", "a,b", "inf,0.05"])
def test_a_bad_bump_is_one_input_error_naming_the_flag(bad):
    with pytest.raises(InputError, match="--bump"):
        parse_bump(bad)
    with pytest.raises(InputError, match="bumps"):
        SimOptions(bumps=(Bump(1.0, -0.1),))


def test_joint_velocity_noise_adds_its_uniform_variance_to_the_sensors_only():
    """Var of the reported joint velocity = the profile's + u^2 / 3; the estimator's tuning keeps the
    profile (it is not told)."""
    plant = build_plant()
    q0 = standing_qpos(plant)
    u, dt = 3.0, plant.dt
    base = noise_profile("typical")
    noisy = with_joint_vel_noise(base, u)
    assert noisy.joint_vel_std(dt) == pytest.approx(math.sqrt(base.joint_vel_std(dt) ** 2 + u**2 / 3))
    s0 = SensorModel(plant.model, base, 0, plant.imu)
    s1 = SensorModel(plant.model, noisy, 0, plant.imu)
    d = mujoco.MjData(plant.model)
    d.qpos[:] = q0
    mujoco.mj_forward(plant.model, d)
    err = np.array([s1.read(d).joints.qd for _ in range(400)])  # the truth is 0
    assert np.std(err) == pytest.approx(noisy.joint_vel_std(dt), rel=0.05)
    assert np.std([s0.read(d).joints.qd for _ in range(50)]) < 0.2 * np.std(err)
    # the controller's settings carry no joint-velocity noise: its estimator is tuned to the profile alone
    assert "joint_vel_noise" not in SimOptions(joint_vel_noise=u).controller_settings().__dict__
    with pytest.raises(InputError, match="joint_vel_noise"):
        SimOptions(joint_vel_noise=-1.0)


def test_the_scenario_sim_block_takes_pushes_bumps_mass_com_offset_strength_and_noise():
    from gaitshift.sim.scenario_run import scenario_options

    sim = SimSettings.model_validate(
        {
            "mass_scale": 1.1,
            "com_offset": [0.02, -0.01, 0.0],
            "motor_strength": 0.9,
            "joint_vel_noise": 0.5,
            "pushes": [{"t": 2.0, "impulse": [0.0, 15.0]}],
            "bumps": [{"x": 1.5, "height": 0.03}],
        }
    )
    kw = scenario_options(SimpleNamespace(sim=sim))
    opts = SimOptions(**kw)
    assert opts.mass_scale == 1.1 and opts.joint_vel_noise == 0.5
    assert opts.com_offset == (0.02, -0.01, 0.0) and opts.motor_strength == 0.9
    assert opts.pushes == (Push(t=2.0, impulse=15.0, duration=0.1, direction=(0.0, 15.0)),)
    assert opts.bumps == (Bump(x=1.5, height=0.03, length=0.2),)
    with pytest.raises(ValueError):
        SimSettings.model_validate({"bumps": [{"x": 1.0, "height": 0.0}]})
    with pytest.raises(ValueError):
        SimSettings.model_validate({"com_offset": [0.0, 0.3, 0.0]})
