"""The start of ``robot tune`` read from the models: the yaw joints found by their axes are the ones the
makers named yaw; the knee capacity of eq. (1) orders the robots as their shipped flights do (the G1's
and H1's full flight, the T1's shorter one, found by bisection before: 0.5); the turn-rate cap of
eq. (2) follows the yaw joints' speed limit (Apollo: its MJCF's hip damping leaves 0.70 rad/s)."""

from __future__ import annotations

import math

import pytest

from gaitshift.robots import load_robot
from gaitshift.tuning.start import starting_gait
from robot_yamls import APOLLO


@pytest.mark.parametrize("name", ["g1", "h1", "op3", "t1"])
def test_the_yaw_joints_found_by_their_axes_are_the_named_ones(name):
    left, right = starting_gait(load_robot(name)).yaw_joints
    assert "yaw" in left.lower() and "yaw" in right.lower()
    assert left != right


def test_the_knee_capacity_orders_the_flights_as_bisection_did():
    g1, h1, t1 = (starting_gait(load_robot(n)) for n in ("g1", "h1", "t1"))
    assert g1.flight_scale == 1.0 and h1.flight_scale == 1.0
    assert 0.3 < t1.flight_scale < 0.7  # shipped 0.5: flights of 0.06-0.08 s ran, 0.09 s fell
    assert t1.knee_ratio < h1.knee_ratio < g1.knee_ratio


def test_the_turn_rate_cap_follows_the_yaw_joints_speed(tmp_path):
    path = tmp_path / "apollo.yaml"
    path.write_text(APOLLO)
    robot = load_robot(path)
    start = starting_gait(robot)
    assert start.yaw_joints == ("l_hip_ie", "r_hip_ie")
    speed = float(robot.damping_speed[robot.joint_names.index("l_hip_ie")])  # torque limit / damping
    assert 0.6 < speed < 0.8
    assert start.max_yaw_rate is not None and start.max_yaw_rate < speed / 2
    assert starting_gait(load_robot("t1")).max_yaw_rate is None  # no speed limit known: no cap
    assert math.isfinite(starting_gait(load_robot("g1")).max_yaw_rate or math.nan)
