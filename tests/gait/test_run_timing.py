"""The running timing law per speed (gaitshift.gait.run_timing): contact length and swing time kept."""

import math

import numpy as np
import pytest

from gaitshift.gait.run_timing import running_stride, running_timing
from gaitshift.robots.config import load_robot


def test_below_the_knee_speed_the_nominal_timing_is_kept():
    ts, tf = running_timing(np.array([0.0, 0.5, 1.5]), 0.32, 0.12, 0.5)
    assert np.allclose(ts, 0.32) and np.allclose(tf, 0.12)


def test_above_it_the_stance_travel_is_the_contact_length_and_the_swing_time_is_kept():
    v = np.linspace(1.6, 3.0, 8)
    ts, tf = running_timing(v, 0.32, 0.12, 0.5)
    assert np.allclose(v * ts, 0.5)  # contact length L_c = v T_s
    assert np.allclose(ts + 2 * tf, 0.32 + 2 * 0.12)  # swing time T_sw = T_s + 2 T_f
    f = 1.0 / (ts + tf)
    assert np.all(np.diff(f) > 0) and np.all(np.diff(tf) > 0)  # step frequency and flight rise
    assert np.allclose(running_stride(v, 0.32, 0.12, 0.5), v * (ts + tf))


def test_an_infinite_contact_length_is_the_fixed_timing_and_bad_input_is_refused():
    ts, tf = running_timing(2.5, 0.32, 0.12, math.inf)
    assert ts == pytest.approx(0.32) and tf == pytest.approx(0.12)
    with pytest.raises(ValueError, match="contact_length"):
        running_timing(1.0, 0.32, 0.12, 0.0)


def test_the_g1_yaml_gives_the_contact_length_and_other_robots_default_to_none():
    assert load_robot("g1").run_contact_length == pytest.approx(0.5)
    assert math.isinf(load_robot("h1").run_contact_length)


def test_g1_top_speed_runs_the_law_timing_of_its_speed_from_g1_runs_nominal_timing():
    from gaitshift.scenario.loader import load_scenario

    top, run = load_scenario("g1-top-speed"), load_scenario("g1-run")
    v = top.profile.max_stride / (top.timing.single_support + top.timing.flight)
    ts, tf = running_timing(v, run.timing.single_support, run.timing.flight, load_robot("g1").run_contact_length)
    assert v == pytest.approx(2.0, abs=1e-3)
    assert top.timing.single_support == pytest.approx(ts, abs=1e-3) and top.timing.flight == pytest.approx(tf, abs=1e-3)
