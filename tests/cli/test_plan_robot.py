"""``wholebody`` and ``animate`` take their robot from the plan: a scenario (or a plan file) that names its
robot is solved for that robot without ``--robot``, and a ``--robot`` naming another robot is refused with
one line and exit 2, as ``simulate`` does (:func:`gaitshift.api.plan_robot`)."""

from __future__ import annotations

import numpy as np

import gaitshift
from gaitshift.api import plan_robot
from gaitshift.wholebody.joints import JointTrajectory
from gaitshift.wholebody.scaling import scale_scenario, scenario_yaml


def test_wholebody_solves_for_the_robot_the_scenario_names(cli, tmp_path):
    scenario = tmp_path / "t1-walk.yaml"
    scenario.write_text(scenario_yaml(scale_scenario("g1-walk", "t1")))
    out = tmp_path / "j.npz"
    code, text, _ = cli(["wholebody", str(scenario), "--rate", "25", "--out", str(out)])
    joints = JointTrajectory.load(out)
    assert code == 0 and text.startswith("t1:") and joints.meta["robot"] == "t1"
    assert joints.qpos.shape[1] == gaitshift.robots.load_robot("t1").model().nq
    assert np.all(np.isfinite(joints.qpos))


def test_a_robot_other_than_the_plans_own_is_one_line_and_exit_2(cli, tmp_path):
    plan_file = tmp_path / "t1-walk.npz"
    gaitshift.plan(scale_scenario("g1-walk", "t1")).save(plan_file)
    code, _, err = cli(["wholebody", str(plan_file), "--robot", "g1", "--out", str(tmp_path / "j.npz")])
    assert code == 2 and err.count("\n") == 1 and "--robot" in err and "'t1'" in err
    assert not (tmp_path / "j.npz").exists()


def test_a_plan_without_a_robot_is_for_the_one_given_else_the_g1():
    traj = gaitshift.plan("paper001-table2-walk-run-walk")
    assert plan_robot(traj, None) == "g1" and plan_robot(traj, "t1") == "t1"
