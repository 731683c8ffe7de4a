"""The VHIP scenario schema of paper 003: timings are whole samples, the stance squats below the
contact heights, commands come in time order, and the run length is bounded."""

import pytest
from pydantic import ValidationError

from gaitshift.scenario.vhip import VhipScenario, ticks


def _loc(data):
    with pytest.raises(ValidationError) as exc:
        VhipScenario.model_validate(data)
    return ".".join(map(str, exc.value.errors()[0]["loc"]))


def test_ticks_accepts_whole_multiples_only():
    assert ticks(0.4, 0.001) == 400 and ticks(0.4003, 0.001) is None


def test_durations_are_whole_samples_of_at_least_4_dt():
    assert _loc({"step_period": 0.4003}) == "step_period"
    assert _loc({"dt": 0.01, "start_double_support": 0.03}) == "start_double_support"
    assert _loc({"stance_ratio": 0.9975}) == "stance_ratio"  # 399 stance samples leave a 1-sample flight


def test_the_stance_squats_below_every_contact_height():
    assert _loc({"heights": {"takeoff": 0.8, "z_low": 0.85}}) == "heights.z_low"


def test_commands_are_in_time_order_and_not_empty():
    assert _loc({"commands": [{"t": 2.0}, {"t": 1.0}]}) == "commands"
    assert _loc({"commands": []}) == "commands"


def test_the_run_length_is_checked_on_stop_at_even_when_it_is_left_out():
    assert _loc({"dt": 0.0002, "step_period": 0.4, "commands": [{"t": 590.0}]}) == "stop_at"
    VhipScenario.model_validate({"dt": 0.002, "commands": [{"t": 590.0}]})
