"""Campaign specs: axes expand to the cartesian product with stable hashes, ranges include their stop,
random samples repeat with their seed, and every bad spec (unknown axis, empty range, negative push,
unknown terrain, unreachable scheduler) is one line, exit 2, and leaves no dataset marked complete."""

from __future__ import annotations

import socket
from pathlib import Path

import pytest

from gaitshift.campaign.axes import AXES
from gaitshift.campaign.cases import case_hash, expand
from gaitshift.campaign.spec import load_spec
from gaitshift.errors import InputError

WALK = Path(__file__).resolve().parents[2] / "docs" / "campaigns" / "g1-walk.yaml"


def _spec(**axes):
    return {"task": "plan", "axes": {"scenario": [str(WALK)], **axes}}


def test_product_size_order_and_hash_independent_of_axis_order():
    """3 speeds x 2 masses = 6 distinct cases; listing the axes in another order gives the same hashes,
    and a hash changes when one parameter changes."""
    a = expand(load_spec(_spec(speed=[0.3, 0.4, 0.5], mass_scale=[1.0, 1.2])))
    b = expand(
        load_spec(
            {"task": "plan", "axes": {"mass_scale": [1.2, 1.0], "speed": [0.5, 0.4, 0.3], "scenario": [str(WALK)]}}
        )
    )
    assert len(a) == 6 and len({c["case_hash"] for c in a}) == 6
    assert {c["case_hash"] for c in a} == {c["case_hash"] for c in b}
    assert {(c["speed"], c["mass_scale"]) for c in a} == {(s, m) for s in (0.3, 0.4, 0.5) for m in (1.0, 1.2)}
    changed = dict(a[0], mass_scale=a[0]["mass_scale"] + 0.01)
    assert case_hash(changed) != a[0]["case_hash"]
    assert case_hash(a[0]) == a[0]["case_hash"]
    assert set(AXES) <= set(a[0])  # every axis is a column of every case


def test_range_includes_stop_and_sample_repeats_with_seed():
    """{start 0.2, stop 2.0, step 0.1} is the 19 speeds 0.2..2.0; a sample of n values lies in
    [low, high] and is the same for the same seed, different for another."""
    sp = load_spec(_spec(speed={"start": 0.2, "stop": 2.0, "step": 0.1})).axis_values()["speed"]
    assert len(sp) == 19 and sp[0] == 0.2 and sp[-1] == 2.0 and sp[9] == 1.1
    s1 = load_spec(_spec(push_impulse={"low": 5, "high": 40, "n": 7, "seed": 3})).axis_values()["push_impulse"]
    s2 = load_spec(_spec(push_impulse={"low": 5, "high": 40, "n": 7, "seed": 3})).axis_values()["push_impulse"]
    s3 = load_spec(_spec(push_impulse={"low": 5, "high": 40, "n": 7, "seed": 4})).axis_values()["push_impulse"]
    assert s1 == s2 != s3 and len(s1) == 7 and all(5 <= v <= 40 for v in s1)


@pytest.mark.parametrize(
    ("axes", "field", "words"),
    [
        ({"wind": [1.0]}, "axes.wind", "axes: robot"),
        ({"speed": {"start": 1.0, "stop": 0.5, "step": 0.1}}, "axes.speed", "empty range"),
        ({"speed": {"start": 0.5, "stop": 1.0, "step": 0.0}}, "axes.speed", "empty range"),
        ({"speed": []}, "axes.speed", "non-empty"),
        ({"push_impulse": [10, -5]}, "axes.push_impulse[1]", "[0, 1000]"),
        ({"terrain": ["known", "stairs"]}, "axes.terrain[1]", "one of: known, blind, perceived"),
        ({"latency": [1.5]}, "axes.latency[0]", "an integer"),
    ],
)
def test_bad_axes_raise_one_input_error(axes, field, words):
    """Each bad axis raises one InputError naming the axis (and item) and what is allowed."""
    with pytest.raises(InputError) as exc:
        expand(load_spec(_spec(**axes)))
    assert exc.value.field == field and words in str(exc.value) and "\n" not in str(exc.value)


def test_locomotion_axis_on_a_planned_scenario_is_refused():
    """``speed`` scales a locomotion command; on a tvlip scenario (g1-walk) it is an error, not ignored."""
    with pytest.raises(InputError, match="locomotion"):
        expand(load_spec({"task": "simulate", "axes": {"scenario": ["g1-walk"], "speed": [0.4]}}))


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.mark.parametrize(
    ("text", "extra", "words"),
    [
        ("task: simulate\naxes: {wind: [1]}\n", [], "axes.wind"),
        ("task: simulate\naxes: {speed: {start: 1, stop: 0, step: 0.5}}\n", [], "empty range"),
        ("task: simulate\naxes: {push_impulse: [-3]}\n", [], "axes.push_impulse[0]"),
        ("task: simulate\naxes: {terrain: [flat]}\n", [], "axes.terrain[0]"),
        ("task: fly\n", [], "task"),
        ("task: plan\naxes: {speed: [0.4]}\n", ["--scheduler", "tcp://127.0.0.1:{port}"], "--scheduler"),
    ],
)
def test_cli_bad_spec_is_one_line_exit_2_and_nothing_complete(cli, tmp_path: Path, text, extra, words):
    """A bad spec or an unreachable scheduler: exit 2, one line on stderr naming the culprit, and no
    ``complete`` marker in the output folder."""
    spec = tmp_path / "spec.yaml"
    spec.write_text(text.replace("axes: {", f"axes: {{scenario: [{WALK}], ", 1) if "axes" in text else text)
    out = tmp_path / "out"
    argv = ["campaign", str(spec), "--out", str(out), *[a.replace("{port}", str(_free_port())) for a in extra]]
    code, stdout, err = cli(argv)
    assert code == 2, (stdout, err)
    assert err.count("\n") == 1 and err.startswith("gaitshift: error: ") and words in err
    assert not (out / "complete").exists()
