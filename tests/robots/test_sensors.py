"""The robot YAML's ``sensors``: every built-in robot has an IMU frame in the controller's model and a
gyro and an accelerometer there in the simulated world; an IMU given as a body and an offset sits
where the offset says (forward kinematics); a robot without foot force (the default, and the G1's
low-level state) senses contact from its motors' torques; the sole force zone covers the whole contact
footprint (the touch sensors read MuJoCo's contact normal force on every built-in robot); bad
``sensors`` values are one-line errors naming the field."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest

from gaitshift.control.settings import contact_source
from gaitshift.errors import InputError
from gaitshift.robots import builtin_robots, load_robot
from gaitshift.robots.model import robot_model, standing_qpos
from gaitshift.robots.sensors import ADDED_IMU_SITE
from gaitshift.sim.contacts import ContactSensor
from gaitshift.sim.plant import build_plant
from gaitshift.sim.sensor_spec import SOLE_TOUCH_SENSORS

T1 = (Path(__file__).parents[2] / "src/gaitshift/robots/configs/t1.yaml").read_text()


def _t1(tmp_path: Path, sensors: str) -> Path:
    text = T1.replace("mjcf: asset:", "mjcf: asset:") + f"\nsensors: {sensors}\n"
    path = tmp_path / "t1x.yaml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("name", builtin_robots())
def test_every_builtin_robot_has_an_imu_with_a_gyro_and_an_accelerometer(name):
    robot = robot_model(name)
    assert mujoco.mj_name2id(robot.model, mujoco.mjtObj.mjOBJ_SITE, robot.imu_site) >= 0
    plant = build_plant(robot=name)
    site = plant.model.site(plant.imu).id
    kinds = {
        int(plant.model.sensor_type[i])
        for i in range(plant.model.nsensor)
        if int(plant.model.sensor_objtype[i]) == int(mujoco.mjtObj.mjOBJ_SITE) and plant.model.sensor_objid[i] == site
    }
    assert {int(mujoco.mjtSensor.mjSENS_GYRO), int(mujoco.mjtSensor.mjSENS_ACCELEROMETER)} <= kinds
    assert plant.imu == robot.imu_site


def test_the_g1_names_its_pelvis_imu_and_has_no_foot_force():
    g1 = load_robot("g1")
    assert g1.imu_site == "imu_in_pelvis" and g1.sensors.imu.body is None
    assert not g1.sensors.foot_force
    assert contact_source(None, g1) == "torque"
    assert contact_source("force", g1) == "force"


def test_an_imu_on_a_body_sits_at_its_offset(tmp_path):
    robot = load_robot(_t1(tmp_path, "{imu: {body: Trunk, pos: [0.01, -0.02, 0.1], quat: [0, 0, 0, 1]}}"))
    assert robot.imu_site == ADDED_IMU_SITE
    for model in (robot.model(), robot_model(robot).model, build_plant(robot=robot).model):
        d = mujoco.MjData(model)
        d.qpos[:] = model.qpos0
        d.qpos[7:] += 0.1  # any pose
        mujoco.mj_kinematics(model, d)
        body = model.body("Trunk").id
        R = d.xmat[body].reshape(3, 3)
        site = model.site(ADDED_IMU_SITE).id
        np.testing.assert_allclose(d.site_xpos[site], d.xpos[body] + R @ [0.01, -0.02, 0.1], atol=1e-12)
        yaw_pi = np.diag([-1.0, -1.0, 1.0])  # (0, 0, 0, 1): half a turn about z
        np.testing.assert_allclose(d.site_xmat[site].reshape(3, 3), R @ yaw_pi, atol=1e-12)


def test_without_sensors_the_imu_is_at_the_floating_base_origin():
    t1 = load_robot("t1")
    assert t1.imu_site == ADDED_IMU_SITE and t1.sensors.imu.body == t1.base
    assert t1.sensors.imu.pos == (0.0, 0.0, 0.0)


@pytest.mark.parametrize("name", builtin_robots())
def test_the_sole_touch_sensors_read_the_contact_normal_force_on_every_robot(name):
    """The robot 1 mm into the floor in its standing pose: every sole contact lies in its zone."""
    plant = build_plant(robot=name)
    m = plant.model
    d = mujoco.MjData(m)
    d.qpos[:] = standing_qpos(plant)
    d.qpos[2] -= 0.001
    mujoco.mj_forward(m, d)
    touch = np.array([d.sensordata[m.sensor(n).adr[0]] for n in SOLE_TOUCH_SENSORS])
    grf = ContactSensor(plant).read(d).grf
    assert np.all(grf[:, 2] > 1.0)
    np.testing.assert_allclose(touch, grf[:, 2], rtol=1e-6)


@pytest.mark.parametrize(
    ("sensors", "field"),
    [
        ("{imu: {site: no_such_site}}", "robot.sensors.imu.site"),
        ("{imu: {body: no_such_body}}", "robot.sensors.imu.body"),
        ("{imu: {site: x, body: Trunk}}", "robot.sensors.imu"),
        ("{imu: {body: Trunk, quat: [0, 0, 0, 0]}}", "robot.sensors.imu"),
        ("{foot_force: 1}", "robot.sensors.foot_force"),
        ("{cameras: 2}", "robot.sensors.cameras"),
    ],
)
def test_bad_sensors_name_the_field(tmp_path, sensors, field):
    with pytest.raises(InputError) as err:
        load_robot(_t1(tmp_path, sensors))
    assert err.value.field == field
    assert "\n" not in str(err.value)
