"""``gaitshift simulate``'s sensing flags: a bad value is one line naming the flag, exit 2, before any
work; a scenario's ``sim:`` block is validated the same way; with ``--json`` stdout is the JSON alone
and carries ``state_source`` and the ``estimation`` object."""

from __future__ import annotations

import json

import pytest
import yaml

import gaitshift
from gaitshift.scenario.loader import builtin_text


@pytest.mark.parametrize(
    ("flag", "value"),
    [
        ("--state", "truth"),
        ("--noise", "loud"),
        ("--noise-scale", "-1"),
        ("--latency", "99"),
        ("--friction", "0"),
        ("--contact", "feelers"),
    ],
)
def test_a_bad_sensing_flag_is_one_line_naming_it_and_exit_2(cli, tmp_path, flag, value):
    out = tmp_path / "o.npz"
    code, _, stderr = cli(["simulate", "g1-walk", "--out", str(out), flag, value])
    assert code == 2
    assert stderr.count("\n") == 1 and flag in stderr
    assert not out.exists()


def test_a_bad_sim_block_in_a_scenario_names_the_key(cli, tmp_path):
    data = yaml.safe_load(builtin_text("g1-walk")) | {"sim": {"noise": "loud"}}
    path = tmp_path / "s.yaml"
    path.write_text(yaml.safe_dump(data))
    code, _, stderr = cli(["simulate", str(path), "--out", str(tmp_path / "o.npz")])
    assert code == 2
    assert stderr.count("\n") == 1 and "sim.noise" in stderr


def test_json_stdout_is_the_json_alone_with_the_estimation_keys(cli, tmp_path):
    data = yaml.safe_load(builtin_text("g1-walk"))
    data["gait"] = [{"gait": "walk", "steps": 2}]
    data["profile"] |= {"accelerate_steps": 1, "decelerate_steps": 1}
    data["sim"] = {"state": "oracle", "seed": 3}
    path = tmp_path / "short.yaml"
    path.write_text(yaml.safe_dump(data))
    assert gaitshift.load_scenario(str(path)).sim.seed == 3
    code, stdout, stderr = cli(["simulate", str(path), "--out", str(tmp_path / "o.npz"), "--json", "--noise", "none"])
    assert code == 0, stderr
    met = json.loads(stdout)
    assert met["state_source"] == "oracle"  # from the scenario's sim block
    keys = {"base_vel_rmse", "tilt_rmse", "yaw_drift", "pos_drift_per_m", "contact_accuracy", "tick_us"}
    assert keys <= set(met["estimation"])
    assert "wrote" in stderr
