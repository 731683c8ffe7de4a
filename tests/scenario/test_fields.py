"""The shared scenario pieces: strict bounded numbers, the foot, the sample budget, and the one-line
conversion of a pydantic error that names the dotted field, the value and the rule."""

import math

import pytest
from pydantic import ValidationError

from gaitshift.errors import InputError, ScenarioError
from gaitshift.scenario.fields import MAX_SAMPLES, Foot, Missing, check_samples, input_error, short_repr
from gaitshift.scenario.tvlip import TvlipScenario


def _error(data, schema=TvlipScenario, **kw) -> InputError:
    with pytest.raises(ValidationError) as exc:
        schema.model_validate(data)
    return input_error(exc.value, schema, **kw)


def test_numbers_are_strict_an_int_is_a_float_but_a_bool_or_a_string_is_not():
    assert TvlipScenario.model_validate({"height": 1}).height == 1.0
    for bad in (True, "0.9", None):
        err = _error({"height": bad})
        assert err.field == "height" and str(err.value) == repr(bad) and err.allowed == "input should be a valid number"
    assert _error({"gait": [{"gait": "walk", "steps": 2.0}]}).field == "gait.0.steps"


def test_nan_inf_and_out_of_range_values_name_the_bound():
    assert _error({"timing": {"flight": math.nan}}).allowed == "a finite number"
    err = _error({"height": 50.0})
    assert (err.field, err.value, err.allowed) == ("height", 50.0, "<= 5.0")
    assert _error({"gravity": 0.0}).allowed == ">= 0.1"


def test_missing_key_is_named_alone_and_shown_as_missing():
    err = _error({"gait": [{"gait": "walk"}]})
    assert err.field == "gait.0.steps" and isinstance(err.value, Missing)
    assert str(err) == "gait.0.steps = missing is invalid: allowed a value (required key)"


def test_short_list_names_the_list_not_the_missing_index():
    err = _error({"foot": {"size": [0.2]}})
    assert err.field == "foot.size" and str(err.value) == "[0.2]" and "item 1 is missing" in err.allowed


def test_unknown_key_lists_the_known_keys_of_its_model():
    err = _error({"timing": {"singel_support": 0.4}})
    assert err.field == "timing.singel_support"
    assert "single_support" in err.allowed and "(unknown key)" in err.allowed and "gait" not in err.allowed


def test_error_class_and_prefix_are_the_callers():
    err = _error({"height": -1.0}, error=ScenarioError, prefix="robot.")
    assert isinstance(err, ScenarioError) and err.field == "robot.height"


def test_foot_margin_must_leave_a_zmp_area():
    with pytest.raises(ValidationError, match="leaves no ZMP area"):
        Foot(size=(0.1, 0.05), zmp_margin=0.03)
    with pytest.raises(ValidationError, match="exceeds upper bound"):
        Foot(zmp_z=(0.01, 0.0))


def test_sample_budget():
    check_samples(MAX_SAMPLES * 1e-3, 1e-3)
    with pytest.raises(ValueError, match="at most"):
        check_samples(MAX_SAMPLES * 1e-3 + 1.0, 1e-3)


def test_short_repr_is_bounded_for_huge_shared_structures():
    big = [1] * 10
    for _ in range(40):  # 10**40 leaves if expanded
        big = [big] * 10
    text = short_repr({"x": big, "s": "y" * 1000})
    assert len(text) <= 80 and "\n" not in text and repr(text) == str(text)
