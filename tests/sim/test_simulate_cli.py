"""``gaitshift simulate --robot``: the robot is chosen explicitly (a scenario made for one robot is not
run on another), errors are one line with exit 2, and a fall exits 1 with valid JSON metrics."""

from __future__ import annotations

import json

import pytest

from gaitshift.cli import main


def _run(args, capsys):
    with pytest.raises(SystemExit) as exc:
        main(list(args))
    out = capsys.readouterr()
    return exc.value.code, out.out, out.err


def test_a_g1_scenario_on_another_robot_is_an_explicit_error(tmp_path, capsys):
    code, _, err = _run(["simulate", "g1-walk", "--robot", "t1", "--out", str(tmp_path / "x.npz")], capsys)
    assert code == 2 and err.count("\n") == 1
    assert "--robot = 't1'" in err and "gaitshift scale g1-walk --robot t1" in err
    assert not (tmp_path / "x.npz").exists()


def test_unknown_robot_lists_the_names_and_a_missing_file_says_no_such_file(tmp_path, capsys):
    code, _, err = _run(
        ["simulate", "paper001-table1-running", "--robot", "nao", "--out", str(tmp_path / "x.npz")], capsys
    )
    assert code == 2 and "berkeley, g1, h1, op3, t1" in err
    code, _, err = _run(["simulate", "g1-walk", "--robot", str(tmp_path / "mine.yaml"), "--out", "x.npz"], capsys)
    assert code == 2 and "no such file" in err


def test_a_fall_exits_1_with_valid_json_metrics(tmp_path, capsys):
    """A lateral impulse of 60 N s on the 33 kg G1 (1.8 m/s sideways at mid-stance of step 4) is a fall."""
    code, out, _ = _run(["simulate", "g1-walk", "--push", "60", "--out", str(tmp_path / "s.npz"), "--json"], capsys)
    metrics = json.loads(out)
    assert code == 1 and metrics["fell"] is True and metrics["fall_time"] > 0
    assert (tmp_path / "s.npz").exists()


def test_a_plan_faster_than_the_makers_joint_speed_limits_is_refused_before_the_simulation(tmp_path, capsys):
    """The H1's velocity_limits (Unitree's h1.urdf) are below what the scaled G1 walk needs of its 5-DoF
    legs at the G1's step timing (the shipped H1 YAML without its ``gait`` choice): simulate stops before
    any physics with one line naming the joint, its speed and its limit."""
    from importlib import resources

    text = (resources.files("gaitshift.robots") / "configs" / "h1.yaml").read_text()
    plain = "\n".join(line for line in text.splitlines() if not line.startswith("gait:"))
    (tmp_path / "h1-plain.yaml").write_text(plain.replace("name: h1", "name: h1-plain"))
    scaled = tmp_path / "h1-walk.yaml"
    assert _run(["scale", "g1-walk", "--robot", str(tmp_path / "h1-plain.yaml"), "--out", str(scaled)], capsys)[0] == 0
    code, _, err = _run(["simulate", str(scaled), "--out", str(tmp_path / "s.npz")], capsys)
    assert code == 2 and err.count("\n") == 1
    assert "rad/s, above its limit" in err and "(velocity_limits)" in err
    assert not (tmp_path / "s.npz").exists()
