"""The standing pose of a robot YAML: a ``standing_pose`` that gives no leg joint (arms only) keeps the
computed leg pose (knees bent to the default CoM height, soles flat) instead of straight legs, with the
given joints held at their values; a pose that gives leg joints is used as given."""

from __future__ import annotations

from importlib import resources

import mujoco
import numpy as np
import yaml

from gaitshift.robots import load_robot
from gaitshift.robots.config import STANDING_HEIGHT_FRACTION
from gaitshift.robots.dimensions import com_height


def _g1_with(pose: dict, tmp_path):
    data = yaml.safe_load((resources.files("gaitshift.robots") / "configs" / "g1.yaml").read_text())
    data["standing_pose"] = pose
    path = tmp_path / "g1-arms.yaml"
    path.write_text(yaml.safe_dump(data))
    return load_robot(path)


def test_an_arms_only_standing_pose_keeps_the_computed_legs(tmp_path):
    robot = _g1_with({"left_elbow_joint": 1.0, "right_elbow_joint": 1.0}, tmp_path)
    pose = dict(robot.standing_pose)
    assert robot.standing_computed
    assert pose["left_elbow_joint"] == 1.0 and pose["right_elbow_joint"] == 1.0
    assert pose["left_knee_joint"] > 0.3 and pose["right_knee_joint"] > 0.3  # bent, not straight
    model = robot.model()
    straight = com_height(model, (("left_elbow_joint", 1.0), ("right_elbow_joint", 1.0)))
    assert abs(robot.com_height - STANDING_HEIGHT_FRACTION * com_height(model, ())) < 1e-4
    assert robot.com_height < straight - 0.02
    d = mujoco.MjData(model)
    d.qpos[:] = robot.standing_qpos(model)
    mujoco.mj_kinematics(model, d)
    for site in robot.SOLE_SITES:  # soles flat
        assert np.allclose(d.site_xmat[model.site(site).id].reshape(3, 3), np.eye(3), atol=1e-6)


def test_a_standing_pose_with_leg_joints_is_used_as_given(tmp_path):
    robot = _g1_with({"left_knee_joint": 0.4, "right_knee_joint": 0.4}, tmp_path)
    assert not robot.standing_computed
    assert dict(robot.standing_pose) == {"left_knee_joint": 0.4, "right_knee_joint": 0.4}
