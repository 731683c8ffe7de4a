"""The simulated plant is the G1 of its robot config, with torque motors at the rated limits.

Oracles: the rated torque limits are read from the MJCF text (``actuatorfrcrange``) independently of
the plant builder; the sole geometry and the standing pose are checked by plain MuJoCo forward
kinematics (:mod:`mujoco_checks`) with the robot YAML's sole offsets.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

import mujoco
import numpy as np
import pytest

from gaitshift.errors import InputError
from gaitshift.robots import load_robot
from gaitshift.robots.model import standing_qpos
from gaitshift.sim.plant import FLOOR, build_plant
from mujoco_checks import forward_kinematics, tilt
from robot_yamls import APOLLO


@pytest.fixture(scope="module")
def plant():
    return build_plant(0.002)


def test_plant_motors_are_limited_to_the_rated_joint_torques(plant):
    xml = load_robot("g1").mjcf.read_text()
    rated = {
        j.get("name"): float(j.get("actuatorfrcrange").split()[1])
        for j in ET.fromstring(xml).iter("joint")
        if j.get("actuatorfrcrange")
    }
    m = plant.model
    assert m.nu == len(rated) == 29
    for i in range(m.nu):
        name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, m.actuator_trnid[i, 0])
        assert m.actuator_ctrlrange[i].tolist() == [-rated[name], rated[name]]
        assert m.actuator_biastype[i] == 0 and m.actuator_gainprm[i, 0] == 1.0  # pure torque motor
    assert m.opt.integrator == mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    assert m.opt.timestep == pytest.approx(0.002)


def test_plant_is_the_config_robot_with_a_floor_added_to_its_mjcf(plant):
    robot = load_robot("g1")
    assert plant.robot == robot
    assert plant.model.geom(plant.floor_geom).name == FLOOR
    assert plant.model.geom_type[plant.floor_geom] == mujoco.mjtGeom.mjGEOM_PLANE
    assert plant.mass == pytest.approx(robot.mass, rel=1e-12)
    names = [mujoco.mj_id2name(plant.model, mujoco.mjtObj.mjOBJ_BODY, s.body) for s in plant.soles]
    assert tuple(names) == robot.sole_bodies
    assert mujoco.mj_id2name(plant.model, mujoco.mjtObj.mjOBJ_BODY, plant.torso_body) == robot.torso
    with pytest.raises(InputError, match="control_period"):
        build_plant(0.005)


def test_sole_centre_of_the_contact_spheres_is_the_yaml_sole_offset(plant):
    robot = load_robot("g1")
    m = plant.model
    for side in (0, 1):
        s = plant.soles[side]
        bottoms = np.array([m.geom_pos[g] - [0.0, 0.0, m.geom_size[g, 0]] for g in s.geoms])
        assert all(m.geom_type[g] == mujoco.mjtGeom.mjGEOM_SPHERE for g in s.geoms)
        np.testing.assert_allclose(bottoms.mean(axis=0), robot.sole_offsets[side], atol=1e-12)
        np.testing.assert_allclose(s.points, bottoms - s.centre, atol=1e-12)
        assert len(s.points) == 4
        assert np.ptp(s.points[:, 2]) < 1e-15  # flat sole


def test_standing_pose_is_the_yaml_pose_with_both_soles_flat_on_the_floor(plant):
    robot = load_robot("g1")
    q = standing_qpos(plant)
    pose = dict(robot.standing_pose)
    m = plant.model
    for j in range(1, m.njnt):
        assert q[m.jnt_qposadr[j]] == pose.get(m.joint(j).name, 0.0), m.joint(j).name
    assert q[3:7].tolist() == [1.0, 0.0, 0.0, 0.0]
    _, soles, rot = forward_kinematics(m, q[None], robot.sole_bodies, robot.sole_offsets)
    np.testing.assert_allclose(soles[0, :, 2], 0.0, atol=1e-12)
    assert np.all(tilt(rot) < 1e-9)
    assert abs(soles[0, 0, 1] - soles[0, 1, 1]) == pytest.approx(robot.foot_separation, abs=1e-9)


@pytest.mark.parametrize("flexion", [0.4, 1.2])
def test_leg_flexion_keeps_the_soles_flat_on_the_floor_and_the_arms_at_the_yaml_pose(plant, flexion):
    robot = load_robot("g1")
    q = standing_qpos(plant, flexion=flexion)
    m = plant.model
    pose = dict(robot.standing_pose)
    for side in (0, 1):
        assert q[m.joint(robot.knees[side]).qposadr[0]] == pytest.approx(flexion * pose[robot.knees[side]])
        assert q[m.joint(robot.hips[side]).qposadr[0]] == pytest.approx(flexion * pose[robot.hips[side]])
    for joint in robot.arm_joints:
        assert q[m.joint(joint).qposadr[0]] == dict(robot.standing_pose).get(joint, 0.0)
    _, soles, rot = forward_kinematics(m, q[None], robot.sole_bodies, robot.sole_offsets)
    np.testing.assert_allclose(soles[0, :, 2], 0.0, atol=1e-12)
    assert np.all(tilt(rot) < 1e-9)


def test_feet_of_a_model_with_frictionless_collision_free_defaults_touch_the_floor_with_friction(tmp_path):
    """Apollo's default geom is ``condim=1 contype=0 conaffinity=0`` (its scene adds foot-floor pairs): the
    floor the plant adds must still collide with the feet, with a friction cone (contact dim 3)."""
    path = tmp_path / "apollo.yaml"
    path.write_text(APOLLO)
    p = build_plant(0.002, path)
    m = p.model
    raw = mujoco.MjModel.from_xml_path(str(load_robot(path).mjcf))
    assert raw.geom_condim[0] == 1 and raw.geom_contype[0] == 0  # the shipped defaults that caused it
    d = mujoco.MjData(m)
    d.qpos[:] = standing_qpos(p)
    d.qpos[2] -= 1e-3  # soles 1 mm into the floor
    mujoco.mj_forward(m, d)
    feet = {g: s for s in (0, 1) for g in p.soles[s].geoms}
    dims = {}
    for c in d.contact[: d.ncon]:
        other = c.geom[1] if c.geom[0] == p.floor_geom else c.geom[0] if c.geom[1] == p.floor_geom else None
        if other in feet:
            dims.setdefault(feet[other], set()).add(int(c.dim))
            assert c.friction[0] > 0
    assert dims == {0: {3}, 1: {3}}
