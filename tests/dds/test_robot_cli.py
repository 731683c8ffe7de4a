"""``gaitshift dds robot`` rejects a bad flag value before it opens any DDS endpoint: one line naming the
flag, the value and what is allowed, exit code 2; and the command is listed in ``gaitshift dds --help``."""

import pytest


@pytest.mark.parametrize(
    ("flags", "name"),
    [
        (["--domain", "300"], "--domain"),
        (["--damping-kd", "-1"], "--damping-kd"),
        (["--duration", "-2"], "--duration"),
        (["--mode-machine", "256"], "--mode-machine"),
    ],
)
def test_a_bad_flag_is_one_line_and_exit_2(cli, flags, name):
    code, _, err = cli(["dds", "robot", "g1", *flags])
    assert code == 2
    assert err.startswith(f"gaitshift: error: {name} = ") and err.count("\n") == 1


def test_the_robot_command_is_listed(cli):
    code, out, _ = cli(["dds", "--help"])
    assert code == 0 and "robot" in out
