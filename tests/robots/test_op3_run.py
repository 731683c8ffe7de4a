"""The ROBOTIS OP3 runs closed loop on its own gait (issue 12): with op3.yaml's choices (standing CoM
0.22 m, strides <= 0.04 m, swing clearance 0.01 m, running flight 0.0375 s, swing gains below the servo
pole b / J) a short walk-run-walk (2 + 4 + 2 steps) finishes every step and the flights are real flights:
both soles measured off the floor for more than a third of the planned time, on the robot's estimator
(an IMU at its base: the OP3's MJCF has none, the simulated world adds it). The joint speeds of the shipped scenarios
stay below the servos' damping bound 4.61 rad/s (torque limit / joint damping of the MJCF)."""

from __future__ import annotations

import numpy as np

import gaitshift
from gaitshift.robots import load_robot
from gaitshift.scenario import load_scenario
from gaitshift.sim.loop import SimOptions, simulate
from gaitshift.wholebody.ik import IKSettings, WholeBodyIK


def test_op3_walk_run_walk_finishes_with_real_flights():
    data = load_scenario("op3-walk-run-walk").model_dump(mode="python")
    data["gait"] = [{"gait": "walk", "steps": 2}, {"gait": "run", "steps": 4}, {"gait": "walk", "steps": 2}]
    data["profile"].update(accelerate_steps=3, decelerate_steps=3)
    traj = gaitshift.plan(load_scenario(data))
    m = simulate(traj, SimOptions(), robot=load_robot("op3")).metrics
    assert m["state_source"] == "estimated"
    assert not m["fell"] and m["steps_completed"] == m["steps_planned"] == 9
    assert m["flight_ratio"] > 0.3 and m["flight_planned_mean"] > 0.03


def test_op3_scenarios_stay_below_the_servo_speed_bound():
    robot = load_robot("op3")
    model = robot.model()
    dofs = [model.jnt_dofadr[model.joint(n).id] for n in robot.joint_names]
    for name in ("op3-walk", "op3-walk-run-walk"):
        sc = load_scenario(name)
        assert sc.robot == "op3"
        ik = WholeBodyIK(robot, IKSettings()).solve(gaitshift.plan(sc), 100.0, check_velocities=False)
        peak = np.max(np.abs(ik.qvel[:, dofs]), axis=0)
        assert np.all(peak < robot.damping_speed), name
