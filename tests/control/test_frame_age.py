"""A frame's age (Controller.tick(frame, age), Controller.measure): a host whose link delays the readings says
how many ticks old they are; the controller acts at the frame's time plus its age, does not measure a frame
twice, and measures the readings a newer frame overtook (gaitshift.dds.lockstep)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gaitshift.control.controller import Controller
from gaitshift.control.frames import SensorFrame
from gaitshift.errors import InputError
from standing import rest_frame


def _rest_frame(c: Controller, t: float) -> SensorFrame:
    """The frame a robot at rest in the start pose reports at ``t`` s (exact sensors, no foot force)."""
    return rest_frame(c, t, foot_force=False)


@pytest.fixture
def ctrl():
    return Controller.from_scenario("g1-walk", settle=0.0)


def test_the_controller_acts_at_the_frames_time_plus_its_age(ctrl):
    """Plan time = frame time + age periods: the reference of a 3-tick-old frame is the plan's 3 ticks on."""
    dt = ctrl.period
    ctrl.tick(_rest_frame(ctrl, 0.0))
    ctrl.tick(_rest_frame(ctrl, 10 * dt), age=3)
    assert ctrl.record is not None and ctrl.record.t == pytest.approx(13 * dt)
    assert ctrl.record.plan_index == round(13 * dt / ctrl.trajectory.dt)


def test_a_frame_repeated_is_not_measured_again(ctrl):
    """A tick that brought no new readings (the frame of the last tick's time, a tick older): the estimator
    does not step, the estimate stays the one of the readings, and the command still comes."""
    dt = ctrl.period
    for k in range(3):
        ctrl.tick(_rest_frame(ctrl, k * dt))
    seen, estimate = ctrl.state.ticks, ctrl.record.estimate
    cmd = ctrl.tick(_rest_frame(ctrl, 2 * dt), age=1)
    assert ctrl.state.ticks == seen and ctrl.record.estimate is estimate
    assert np.all(np.isfinite(cmd.tau))
    ctrl.tick(_rest_frame(ctrl, 4 * dt))  # new readings (one lost between): measured
    assert ctrl.state.ticks == seen + 1 and ctrl.record.estimate is not estimate


def test_readings_a_newer_frame_overtook_are_measured_without_a_command(ctrl):
    """Two frames came at one tick: the older is measured (the estimator steps on it, no command, no record),
    the newer is acted on."""
    dt = ctrl.period
    ctrl.tick(_rest_frame(ctrl, 0.0))
    before = ctrl.record
    ctrl.measure(_rest_frame(ctrl, dt))
    assert ctrl.state.ticks == 2 and ctrl.record is before
    ctrl.tick(_rest_frame(ctrl, 2 * dt))
    assert ctrl.state.ticks == 3 and ctrl.record.t == pytest.approx(2 * dt)


@pytest.mark.parametrize("age", [-1, 11, True, 1.5, "2"])
def test_a_bad_age_is_one_input_error_naming_it(ctrl, age):
    with pytest.raises(InputError, match=r"^age = "):
        ctrl.tick(_rest_frame(ctrl, 0.0), age=age)


def test_a_bad_overtaken_frame_is_one_input_error_naming_its_field(ctrl):
    frame = _rest_frame(ctrl, 0.0)
    with pytest.raises(InputError, match=r"SensorFrame\.q"):
        ctrl.measure(dataclasses.replace(frame, q=np.full(ctrl.robot.model.nu, np.nan)))


def test_a_live_plan_follows_a_host_whose_clock_is_off_the_periods_grid():
    """A host on a wall clock (ticks 0.3 periods early or late): the tick's time is taken to the nearest
    period, so the live generator follows it as it follows exact times (it re-plans only at instants on its
    grid: before, such a host's live plan never moved on)."""
    scenario = {"planner": "locomotion", "robot": "g1", "gait": "walk", "commands": [{"t": 0.0, "vx": 0.2}]}
    exact, jittered = (Controller.from_scenario({**scenario, "stop_at": 2.0}, settle=0.0) for _ in range(2))
    dt = exact.period
    for k in range(300):  # 0.6 s: past the first step's planning instant
        exact.tick(_rest_frame(exact, k * dt))
        jittered.tick(_rest_frame(jittered, k * dt + (0.3 if k % 2 else -0.3) * dt * (k > 0)))
    assert exact.driver.gen.step_count >= 1
    assert jittered.driver.gen.tick_index == exact.driver.gen.tick_index
    assert jittered.driver.gen.step_count == exact.driver.gen.step_count
    np.testing.assert_array_equal(jittered.trajectory.com_pos, exact.trajectory.com_pos)
