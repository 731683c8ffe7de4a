"""``gaitshift robots [ROBOT ...]``: without arguments one line per built-in robot; with a robot YAML
of one's own the same line for it (it took no argument before); a bad one is one error line, exit 2,
and nothing else printed."""

from __future__ import annotations

from importlib import resources


def _line_numbers(line: str) -> list[str]:
    return line.split(": ", 1)[1].split(", ")


def test_a_robot_yaml_of_ones_own_is_described_like_the_builtins(cli, tmp_path):
    code, out, _ = cli(["robots"])
    builtin = next(x for x in out.splitlines() if x.startswith("t1 "))
    path = tmp_path / "mine.yaml"
    text = (resources.files("gaitshift.robots") / "configs" / "t1.yaml").read_text()
    path.write_text(text.replace("name: t1", "name: mine"))
    code, out, err = cli(["robots", str(path)])
    assert code == 0, err
    assert len(out.splitlines()) == 1 and out.startswith("mine ")
    assert _line_numbers(out.strip()) == _line_numbers(builtin)


def test_a_missing_robot_yaml_is_one_error_line(cli, tmp_path):
    code, out, err = cli(["robots", "g1", str(tmp_path / "nope.yaml")])
    assert code == 2 and out == "" and err.count("\n") == 1 and "no such file" in err


def test_each_line_says_where_the_imu_is_and_whether_the_soles_measure_force(cli):
    code, out, _ = cli(["robots", "g1", "op3"])
    g1, op3 = out.splitlines()
    assert code == 0 and g1.endswith("IMU site imu_in_pelvis, no foot force")
    assert op3.endswith("IMU on body_link, no foot force")  # the OP3's floating base: its MJCF has no IMU
