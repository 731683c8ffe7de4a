"""The TV-LIPM scenario schema: defaults plan paper 001's walk, footholds one per step, and the
planned duration (and with it the sample count) is bounded before any planning."""

import pytest
from pydantic import ValidationError

from gaitshift.scenario.fields import MAX_SAMPLES
from gaitshift.scenario.tvlip import Segment, Timing, TvlipScenario, duration


def test_duration_adds_start_stop_steps_and_the_closing_step():
    tm = Timing(single_support=0.4, double_support=0.15, flight=0.1, start=0.8, stop=1.0)
    gait = (Segment(gait="walk", steps=2), Segment(gait="run", steps=3))
    # by hand: 0.8 + 1.0 + 2 (0.4 + 0.15) + 3 (0.4 + 0.1) + (0.4 + 0.15)
    assert duration(tm, gait) == pytest.approx(0.8 + 1.0 + 1.1 + 1.5 + 0.55)


def test_explicit_footholds_need_one_per_step():
    TvlipScenario(gait=(Segment(gait="walk", steps=1),), footsteps=((0.3, -0.1, 0.0, 0.0),))
    with pytest.raises(ValidationError, match="one foothold per step of gait"):
        TvlipScenario(gait=(Segment(gait="walk", steps=2),), footsteps=((0.3, -0.1, 0.0, 0.0),))


def test_too_many_samples_is_rejected_on_dt_even_when_dt_is_the_default():
    steps = int(MAX_SAMPLES * 1e-3 / 0.55) + 10
    with pytest.raises(ValidationError) as exc:
        TvlipScenario.model_validate({"gait": [{"gait": "walk", "steps": steps}]})
    assert exc.value.errors()[0]["loc"] == ("dt",)
    TvlipScenario.model_validate({"gait": [{"gait": "walk", "steps": steps}], "dt": 0.01})


@pytest.mark.parametrize(
    "data",
    [{"dt": 5e-5}, {"profile": {"yaw_rate": 4.0}}, {"timing": {"single_support": 2.5}}, {"height": 0.01}],
)
def test_physical_ranges(data):
    with pytest.raises(ValidationError):
        TvlipScenario.model_validate(data)
