"""``gaitshift scale --robot PATH --out FILE`` writes the robot's YAML path relative to the output
file's folder (it wrote an absolute path), and the written scenario then plans from any working
directory, its relative robot path read from the scenario's folder."""

from __future__ import annotations

from importlib import resources

import yaml


def test_the_scaled_scenario_names_its_robot_relative_to_itself(cli, tmp_path, monkeypatch):
    (tmp_path / "robots").mkdir()
    (tmp_path / "scenarios").mkdir()
    (tmp_path / "elsewhere").mkdir()
    robot = tmp_path / "robots" / "t1-copy.yaml"
    robot.write_text((resources.files("gaitshift.robots") / "configs" / "t1.yaml").read_text())
    out = tmp_path / "scenarios" / "walk.yaml"
    code, _, err = cli(["scale", "g1-walk", "--robot", str(robot), "--out", str(out)])
    assert code == 0, err
    assert yaml.safe_load(out.read_text())["robot"] == "../robots/t1-copy.yaml"
    monkeypatch.chdir(tmp_path / "elsewhere")
    code, _, err = cli(["plan", str(out), "--out", str(tmp_path / "plan.npz")])
    assert code == 0, err
