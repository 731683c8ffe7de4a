"""Scaling a ``planner: locomotion`` scenario (live commands) to a robot: ``gaitshift scale g1-tour``
works (it crashed on the unset ``height``), the scaled scenario plans, its set numbers follow the rule
(lambda = h'/h: speeds x lambda with the timing kept, durations x sqrt(lambda) and speeds x sqrt(lambda)
with Froude timing), the keys it leaves out default from the new robot, and the robot YAML's ``gait``
choices reach it (Berkeley: steps 0.24 m wide, flight x 0.25 of its default)."""

from __future__ import annotations

import math

import pytest
import yaml

import gaitshift
from gaitshift.planners.locomotion.params import params_from_scenario
from gaitshift.robots import load_robot
from gaitshift.scenario import load_scenario
from gaitshift.wholebody.scaling import scale_factor, scale_scenario


def test_the_tour_scaled_to_berkeley_plans_on_its_numbers():
    tour, robot = load_scenario("g1-tour"), load_robot("berkeley")
    lam = robot.com_height / load_robot("g1").com_height
    assert scale_factor(tour, robot) == pytest.approx(lam)
    scaled = scale_scenario(tour, robot)
    for a, b in zip(tour.commands, scaled.commands, strict=True):
        assert (b.t, b.yaw_rate) == (a.t, a.yaw_rate) and b.vx == pytest.approx(lam * a.vx)
    assert scaled.height is None and scaled.foot.size is None  # left out: from the robot's facts
    default = params_from_scenario(tour.model_copy(update={"robot": "berkeley"}), robot.facts())
    p = params_from_scenario(scaled, robot.facts())
    assert p.height == pytest.approx(robot.com_height) and p.foot_size == robot.sole_size
    assert p.step_width == 0.24 and scaled.timing.flight == pytest.approx(0.25 * default.timing.flight)
    traj = gaitshift.plan(scaled)
    assert traj.meta["height"] == pytest.approx(robot.com_height) and traj.meta["step_width"] == 0.24
    assert traj.meta["timing"]["flight"] == pytest.approx(0.25 * default.timing.flight, abs=traj.dt)


def test_froude_timing_scales_durations_and_speeds_by_sqrt_lambda():
    tour = load_scenario("g1-tour")
    lam = scale_factor(tour, "t1")
    scaled = scale_scenario(tour, "t1", time_scale="froude")
    assert scaled.stop_at == pytest.approx(tour.stop_at * math.sqrt(lam))
    for a, b in zip(tour.commands, scaled.commands, strict=True):
        assert b.t == pytest.approx(a.t * math.sqrt(lam)) and b.vx == pytest.approx(a.vx * math.sqrt(lam))


def test_the_scale_command_writes_a_locomotion_scenario_that_plans(cli, tmp_path):
    out = tmp_path / "t1-tour.yaml"
    code, _, err = cli(["scale", "g1-tour", "--robot", "t1", "--out", str(out)])
    assert code == 0, err
    data = yaml.safe_load(out.read_text())
    assert data["planner"] == "locomotion" and data["robot"] == "t1"
    assert gaitshift.plan(str(out)).meta["height"] == pytest.approx(load_robot("t1").com_height)
