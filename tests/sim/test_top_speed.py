"""Top speed on the simulated G1 (issue 13, docs/simulation.md "Top speed"): a short g1-top-speed
(14 running steps, 2 at the constant stride) at 2.0 m/s holds with the running timing law of the
robot (gaitshift.gait.run_timing) and falls with the fixed g1-run timing at the same speed."""

from __future__ import annotations

import yaml

import gaitshift
from gaitshift.gait.run_timing import running_timing
from gaitshift.robots import load_robot
from gaitshift.scenario.loader import builtin_text, load_scenario
from gaitshift.sim.loop import SimOptions, simulate


def _short_run(speed: float, contact_length: float):
    base = yaml.safe_load(builtin_text("g1-top-speed"))
    nominal = yaml.safe_load(builtin_text("g1-run"))["timing"]
    ts, tf = (float(x) for x in running_timing(speed, nominal["single_support"], nominal["flight"], contact_length))
    data = dict(
        base,
        name="g1-top-speed-short",
        gait=[{"gait": "run", "steps": 14}],
        timing=dict(base["timing"], single_support=ts, flight=tf),
        profile=dict(base["profile"], max_stride=speed * (ts + tf)),
    )
    return simulate(gaitshift.plan(load_scenario(data)), SimOptions(state="oracle"))


def test_two_metres_per_second_holds_with_the_timing_law_and_falls_with_the_fixed_timing():
    law = _short_run(2.0, load_robot("g1").run_contact_length)
    assert not law.fell, law.metrics.get("fall_reason")
    assert law.metrics["qp_failures"] == 0
    a = law.arrays
    fast = a["t"] > 3.0
    assert a["com_vel"][fast, 0].max() >= 1.9  # it really ran at about 2 m/s
    fixed = _short_run(2.0, float("inf"))
    assert fixed.fell
