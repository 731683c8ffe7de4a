"""The locomotion generator drives the simulated G1 closed loop: a short tour (walk, turn while
walking, run with an automatic switch, stop) finishes without a fall, its running steps leave the
ground, and the measured stride speed and heading follow the plan (issue 11's aims: 0.1 m/s, 0.1 rad)."""

from __future__ import annotations

import pytest

import gaitshift
from gaitshift.api import robot_facts
from gaitshift.control.drivers import driver_for
from gaitshift.sim.loop import SimOptions, simulate

SHORT_TOUR = {
    "planner": "locomotion",
    "name": "short-tour",
    "robot": "g1",
    "commands": [{"t": 0.0, "vx": 0.5}, {"t": 3.0, "vx": 0.5, "yaw_rate": 0.4}, {"t": 5.0, "vx": 1.5}],
    "stop_at": 9.0,
}


@pytest.fixture(scope="module")
def tour_run():
    sc = gaitshift.load_scenario(SHORT_TOUR)
    drv = driver_for(sc, robot_facts(sc), 0.002)
    assert drv is not None and drv.step_feedback
    return drv, simulate(drv.trajectory, SimOptions(state="oracle"), driver=drv)  # the controller on the truth


def test_the_short_tour_finishes_without_a_fall_and_with_flight(tour_run):
    drv, result = tour_run
    met = result.metrics
    assert not result.fell, met.get("fall_reason")
    assert met["steps_completed"] == met["steps_planned"] >= 20
    assert (drv.trajectory.gait == 2).any() and (drv.trajectory.gait == 1).any()
    assert met["flight_ratio"] >= 0.7


def test_measured_stride_speed_and_heading_follow_the_plan(tour_run):
    _, result = tour_run
    met = result.metrics
    assert len(met["stride_speed_errors"]) >= 5
    assert met["stride_speed_error_max"] <= 0.1
    assert met["heading_error_rms"] <= 0.1
