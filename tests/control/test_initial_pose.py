"""Initial pose of a run: the robot stands on the plan's first footholds with the plan's first CoM.

Checked by plain MuJoCo forward kinematics (:mod:`mujoco_checks`): body-CoM average and sole poses
from the robot YAML's sole offsets.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import gaitshift
from gaitshift.control.initial_pose import initial_qpos, sensed_start
from gaitshift.control.plan_samples import PlanSamples
from gaitshift.errors import InputError
from gaitshift.sim.plant import build_plant
from mujoco_checks import forward_kinematics, tilt, yaw


@pytest.fixture(scope="module")
def plant():
    return build_plant(0.002)


@pytest.mark.parametrize("heading", [0.0, 0.3])
def test_initial_pose_puts_com_and_soles_on_the_plan(plant, heading):
    traj = gaitshift.plan("g1-walk")
    yaws = PlanSamples.from_trajectory(traj).yaw[0] + heading
    com = traj.com_pos[0] + [0.01, 0.0, 0.0]
    q = initial_qpos(plant, com, traj.foot_pos[0], yaws)
    r = plant.robot
    c, soles, rot = forward_kinematics(plant.model, q[None], r.sole_bodies, r.sole_offsets)
    np.testing.assert_allclose(c[0], com, atol=1e-5)
    np.testing.assert_allclose(soles[0], traj.foot_pos[0], atol=1e-5)
    np.testing.assert_allclose(yaw(rot[0]), yaws, atol=1e-5)
    assert np.all(tilt(rot[0]) < 1e-5)


def test_feet_out_of_reach_are_an_input_error(plant):
    feet = np.array([[0.0, 0.6, 0.0], [0.0, -0.6, 0.0]])
    with pytest.raises(InputError, match="initial stance"):
        initial_qpos(plant, np.array([0.0, 0.0, 0.6]), feet, np.zeros(2), iters=50)


def _mat(quat):
    m = np.zeros(9)
    mujoco.mju_quat2Mat(m, quat)
    return m.reshape(3, 3)


def _sole_normals_and_floor(plant, q):
    d = mujoco.MjData(plant.model)
    d.qpos[:] = q
    mujoco.mj_kinematics(plant.model, d)
    normals = [plant.sole_frame(d, s)[1][:, 2] for s in (0, 1)]
    return normals, min(float(plant.contact_points(d, s)[:, 2].min()) for s in (0, 1))


def test_the_sensed_start_puts_the_soles_level_at_the_plans_floor_with_the_measured_joints(plant):
    """A stand-up that ends with other ankle and knee angles than the plan's: the start state keeps those
    angles, turns the base so that the soles' mean normal is vertical, keeps the heading, and puts the
    lowest sole point at the plan's floor; the plan's own pose (soles level) comes back unchanged."""
    traj = gaitshift.plan("g1-walk")
    q0 = initial_qpos(plant, traj.com_pos[0], traj.foot_pos[0], PlanSamples.from_trajectory(traj).yaw[0] + 0.3)
    dofs = plant.actuated_dofs
    motors = q0[plant.model.jnt_qposadr[plant.model.dof_jntid[dofs]]]
    np.testing.assert_allclose(sensed_start(plant, q0, motors), q0, atol=1e-6)  # the IK levels to 1e-6
    names = plant.motor_names
    bent = motors.copy()
    for joint, delta in (("left_knee_joint", 0.04), ("right_knee_joint", 0.04), ("left_ankle_pitch_joint", -0.05)):
        bent[names.index(joint)] += delta
    start = sensed_start(plant, q0, bent)
    (n_left, n_right), floor = _sole_normals_and_floor(plant, start)
    mean = (n_left + n_right) / np.linalg.norm(n_left + n_right)
    np.testing.assert_allclose(mean, [0.0, 0.0, 1.0], atol=1e-9)
    assert floor == pytest.approx(_sole_normals_and_floor(plant, q0)[1], abs=1e-9)
    assert yaw(_mat(start[3:7])) == pytest.approx(yaw(_mat(q0[3:7])), abs=0.01)
    assert tilt(_mat(start[3:7])) > 0.01  # the bent legs tilt the base: what the plan's pose would have missed
    np.testing.assert_array_equal(start[plant.model.jnt_qposadr[plant.model.dof_jntid[dofs]]], bent)
