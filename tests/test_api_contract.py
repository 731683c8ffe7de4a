"""The public Python API's error contract (issue 28): ``gaitshift.stiffness`` on any arguments (numbers in
and out of range, strings, None, sequences, booleans, NaN, infinities, huge values) ends in a
``Stiffness`` of finite numbers or one ``GaitshiftError`` on one line, never another exception; and
``Replanner.replan`` refuses a measured state that is not two finite numbers (it used to return NaN
references)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import gaitshift

ANY = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(-(10**6), 10**6),
    st.sampled_from([0.95, 0.4, 0.15, 0.15, 1e-3, 60.0, 1e300, -0.0, True, None, "a", [1, 2], np.float64(0.3)]),
)


@settings(max_examples=300, deadline=None)
@given(ANY, ANY, ANY, ANY)
def test_stiffness_ends_in_a_result_or_one_line(h, ss, ds, f):
    try:
        k = gaitshift.stiffness(h, ss, ds, f)
    except gaitshift.GaitshiftError as exc:
        assert "\n" not in str(exc)
        return
    assert all(math.isfinite(x) for x in (k.T_w, k.T_r, k.v_r, k.T_t0, k.T_t1))


@pytest.mark.parametrize(
    ("p", "v", "field"),
    [([0.3, np.inf], [0.5, 0.0], "p_xy"), ([0.3, 0.0], [np.nan, 0.0], "v_xy"), ([1.0], [0.0, 0.0], "p_xy"),
     ("ab", [0.0, 0.0], "p_xy")],
)  # fmt: skip
def test_replan_refuses_a_measured_state_that_is_not_two_finite_numbers(p, v, field):
    r = gaitshift.Replanner.from_scenario(gaitshift.load_scenario("paper001-table2-walk-run-walk"))
    with pytest.raises(gaitshift.InputError) as info:
        r.replan(2.0, p, v)
    assert info.value.field == field


def _settings(**given: object) -> object:
    from gaitshift.control.settings import ControllerSettings

    return ControllerSettings.of(**given)


def _noise_profile(name: object) -> object:
    from gaitshift.control.estimation.noise import noise_profile

    return noise_profile(name)  # type: ignore[arg-type]


def _planner_for(name: object) -> object:
    from gaitshift.planners.registry import planner_for

    return planner_for(name)  # type: ignore[arg-type]


CHOICE_CALLS = {
    "ControllerSettings.noise": ("noise", lambda v: _settings(noise=v)),
    "ControllerSettings.state": ("state", lambda v: _settings(state=v)),
    "ControllerSettings.replan": ("replan", lambda v: _settings(replan=v)),
    "noise_profile": ("noise", _noise_profile),
    "planner_for": ("planner", _planner_for),
}


@pytest.mark.parametrize("call", sorted(CHOICE_CALLS))
@pytest.mark.parametrize("value", ["no-such-name", {"a": 1}, ["typical"], 3, None])
def test_a_choice_outside_its_names_is_one_line_naming_the_field_and_the_names(call, value):
    field, fn = CHOICE_CALLS[call]
    if value is None and field == "state":
        fn(value)  # None is allowed there: the robot's own default
        return
    with pytest.raises(gaitshift.GaitshiftError) as info:
        fn(value)
    text = str(info.value)
    assert "\n" not in text and text.startswith(f"{field} = ") and "allowed one of: " in text
