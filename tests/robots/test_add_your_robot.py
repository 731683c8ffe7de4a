"""docs/robots.md "Add your robot", followed step by step: the YAML block of the page is written to a
file and every command of its console block is run, in order, on Apollo (a model of the asset package
that gaitshift ships no config for). Nothing of the page is copied here, so the page cannot drift.

Oracles: the robot is not a built-in; each command exits 0; the whole-body joint trajectories put the
sole sites where the plan's footholds are (forward kinematics of the MJCF); the simulation log shows no
fall and the robot's base ends near the plan's final CoM."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import mujoco
import numpy as np
import pytest

from gaitshift.cli import main
from gaitshift.robots import builtin_robots, load_robot
from gaitshift.scenario import load_scenario

DOC = Path(__file__).resolve().parents[2] / "docs" / "robots.md"


def _section() -> str:
    text = DOC.read_text()
    start = text.index("## Add your robot")
    return text[start : text.index("\n## ", start + 1)]


def _block(section: str, lang: str) -> str:
    match = re.search(rf"```{lang}\n(.*?)```", section, re.S)
    assert match, f"no {lang} block in the walk-through"
    return "\n".join(line[3:] if line.startswith("   ") else line for line in match.group(1).splitlines())


def test_the_add_your_robot_walk_through_runs_as_written(tmp_path, monkeypatch, capsys):
    section = _section()
    yaml_text = _block(section, "yaml")
    name = re.search(r"^name: (\S+)", yaml_text, re.M).group(1)
    assert name not in builtin_robots()
    robot_file = tmp_path / f"{name}.yaml"
    robot_file.write_text(yaml_text)
    monkeypatch.chdir(tmp_path)
    commands = [line.strip() for line in _block(section, "console").splitlines() if line.strip()]
    assert [c.split()[1] for c in commands] == ["robot", "scale", "wholebody", "simulate"]
    for command in commands:
        argv = shlex.split(command)
        assert argv[0] == "gaitshift"
        with pytest.raises(SystemExit) as exc:
            main(argv[1:])
        assert exc.value.code in (0, None), f"{command}: {capsys.readouterr()}"
    robot = load_robot(robot_file)
    scenario = next(Path(a) for c in commands for a in shlex.split(c) if a.endswith("-walk.yaml"))
    assert load_robot(load_scenario(scenario).robot) == robot  # the scaled scenario names its robot
    joints = np.load(next(tmp_path.glob("*-joints.npz")))
    m = robot.model()
    d = mujoco.MjData(m)
    d.qpos[:] = joints["qpos"][-1]
    mujoco.mj_kinematics(m, d)
    soles = np.array([d.site(s).xpos for s in robot.SOLE_SITES])
    sim = np.load(next(p for p in tmp_path.glob("*.npz") if "joints" not in p.name))
    assert not bool(sim["fell"])
    assert soles[:, 2].max() < 0.01  # standing on the floor at the end of the plan
    end = sim["com_pos"][-1]
    assert abs(end[0] - sim["com_ref"][-1][0]) < 0.2 and end[0] > 1.0
