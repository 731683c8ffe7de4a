"""Initial pose of a run: the robot stands on the plan's first footholds with the plan's first CoM.

Checked by plain MuJoCo forward kinematics (:mod:`mujoco_checks`): body-CoM average and sole poses
from the robot YAML's sole offsets.
"""

from __future__ import annotations

import numpy as np
import pytest

import gaitshift
from gaitshift.control.initial_pose import initial_qpos
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
