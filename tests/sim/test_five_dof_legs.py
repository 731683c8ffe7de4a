"""A robot whose legs cannot roll their feet (Unitree H1: 5-DoF legs, no ankle roll) walks closed loop on
the G1 walk scaled to it with its YAML's quicker, shorter steps (``gait: {step_time_scale}``): no fall,
every step taken, the pelvis kept within 20 deg of level (docs/robots.md, H1)."""

from __future__ import annotations

import gaitshift
from gaitshift.robots import load_robot
from gaitshift.sim.loop import SimOptions, simulate
from gaitshift.wholebody.scaling import scale_scenario


def test_the_h1_walks_the_scaled_g1_walk_with_its_quicker_steps():
    robot = load_robot("h1")
    assert robot.foot_roll == (False, False) and robot.step_time_scale < 1.0
    traj = gaitshift.plan(scale_scenario("g1-walk", robot))
    m = simulate(traj, SimOptions(state="oracle"), robot=robot).metrics
    assert not m["fell"] and m["steps_completed"] == m["steps_planned"] == 11
    assert m["max_pelvis_tilt_deg"] < 20.0
