"""Sample specs (``sample: {cases, seed}``): N random cases, each axis drawn from its interval or list,
the same cases for the same seed, one axis's draws independent of the others, the shipped survival
spec inside the RL box it claims; intervals outside a sample spec and two push axes at once refused;
a push given as a velocity is the impulse that gives the simulated robot's mass that velocity."""

from __future__ import annotations

from pathlib import Path

import mujoco
import pytest

from gaitshift.campaign.cases import expand
from gaitshift.campaign.execute import sim_options
from gaitshift.campaign.spec import load_spec
from gaitshift.errors import InputError
from gaitshift.robots import load_robot

DOCS = Path(__file__).resolve().parents[2] / "docs" / "campaigns"
WALK = DOCS / "g1-walk.yaml"


def _sample(n=200, seed=3, **axes):
    return {"task": "simulate", "sample": {"cases": n, "seed": seed}, "axes": {"scenario": [str(WALK)], **axes}}


def test_a_sample_spec_draws_n_cases_inside_every_interval_and_list():
    spec = _sample(speed={"low": 0.2, "high": 1.5}, latency={"low": 0, "high": 4}, noise=["typical", "rl-peer"])
    cases = expand(load_spec(spec), check=False)
    assert len(cases) == 200 and len({c["case_hash"] for c in cases}) == 200
    speeds = [c["speed"] for c in cases]
    assert min(speeds) >= 0.2 and max(speeds) <= 1.5 and max(speeds) - min(speeds) > 1.0
    assert {c["latency"] for c in cases} == {0, 1, 2, 3, 4} and all(isinstance(c["latency"], int) for c in cases)
    assert {c["noise"] for c in cases} == {"typical", "rl-peer"}
    assert {c["mass_scale"] for c in cases} == {1.0}  # not given: its default


def test_the_same_seed_gives_the_same_cases_and_an_added_axis_leaves_the_others_draws():
    a = expand(load_spec(_sample(speed={"low": 0.0, "high": 2.0})), check=False)
    b = expand(load_spec(_sample(speed={"low": 0.0, "high": 2.0})), check=False)
    c = expand(load_spec(_sample(speed={"low": 0.0, "high": 2.0}, friction={"low": 0.3, "high": 1.2})), check=False)
    d = expand(load_spec(_sample(seed=4, speed={"low": 0.0, "high": 2.0})), check=False)
    assert [x["case_hash"] for x in a] == [x["case_hash"] for x in b]
    assert [x["speed"] for x in a] == [x["speed"] for x in c]
    assert [x["speed"] for x in a] != [x["speed"] for x in d]


def test_the_shipped_survival_spec_draws_2000_cases_inside_the_rl_box():
    cases = expand(load_spec(DOCS / "g1-survival.yaml"))
    assert len(cases) >= 2000
    box = {"speed": (0, 2), "push_velocity": (0, 0.5), "friction": (0.3, 1.2), "mass_scale": (0.9, 1.1),
           "com_offset_x": (-0.05, 0.05), "com_offset_y": (-0.05, 0.05), "motor_strength": (0.9, 1.1),
           "latency": (0, 4)}  # fmt: skip
    for axis, (lo, hi) in box.items():
        vals = [c[axis] for c in cases]
        assert lo <= min(vals) and max(vals) <= hi and max(vals) - min(vals) > 0.9 * (hi - lo), axis
    assert {c["state"] for c in cases} == {"estimated"} and {c["noise"] for c in cases} == {"typical", "rl-peer"}
    directions = sorted(c["push_direction"] for c in cases)
    assert directions[0] < 10 and directions[-1] > 350  # any horizontal direction


@pytest.mark.parametrize(
    ("spec", "field"),
    [({"task": "plan", "axes": {"scenario": [str(WALK)], "speed": {"low": 0, "high": 1}}}, "axes.speed"),
     (_sample(noise={"low": 0, "high": 1}), "axes.noise"),
     (_sample(speed={"low": 1.0, "high": 0.5}), "axes.speed.high"),
     (_sample(speed={"low": 0.0, "high": 50.0}), "axes.speed[1]"),
     (_sample(push_impulse=[0, 5], push_velocity=[0.2]), "axes.push_velocity"),
     ({**_sample(), "sample": {"cases": 0}}, "sample.cases")],
)  # fmt: skip
def test_a_bad_sample_or_interval_is_one_input_error_naming_its_field(spec, field):
    with pytest.raises(InputError) as info:
        load_spec(spec)
    assert info.value.field == field and "\n" not in str(info.value)


def test_a_push_velocity_is_the_impulse_of_the_simulated_mass_at_that_speed():
    """J = s M v: the momentum the push gives a rigid robot of mass s M (mj_getTotalmass of the model)."""
    case = expand(load_spec(_sample(n=1, push_velocity=[0.4], mass_scale=[1.1], push_direction=[90.0])), check=False)
    cfg = load_robot("g1")
    push = sim_options(case[0], cfg)["pushes"][0]
    assert push.impulse == pytest.approx(0.4 * 1.1 * mujoco.mj_getTotalmass(cfg.model()), rel=1e-12)
    assert push.direction == pytest.approx((0.0, 1.0), abs=1e-12)
