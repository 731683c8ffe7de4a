"""The live flags of ``gaitshift dds control`` (:mod:`gaitshift.cli.dds_live`): a bad ``--web-port``,
``--teleop`` without a terminal on stdin and ``--teleop`` on a scenario that takes no live command are each
one line naming the flag, the value and what is allowed, exit 2, before anything is built. ``--web`` and
``--teleop`` do not conflict: together (stdin a pseudo-terminal) the page's queue and the keyboard's both
feed the one command input, a key typed reaching it; ``--web`` on a plan without live commands is a view
without controls."""

import io
import os
import pty
import socket
import sys
import time
from types import SimpleNamespace

import pytest

from dds_processes import TINY
from gaitshift.cli.dds_live import check_live_flags, live_inputs
from gaitshift.dds.cmdvel import CommandInput, CommandLimits


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.fixture
def tiny(tmp_path):
    path = tmp_path / "tiny.yaml"
    path.write_text(TINY)
    return str(path)


@pytest.fixture
def tty_stdin(monkeypatch):
    """stdin a pseudo-terminal's slave side; yields the master fd to type on."""
    master, slave = pty.openpty()
    stdin = os.fdopen(slave, "r")
    monkeypatch.setattr(sys, "stdin", stdin)
    yield master
    stdin.close()
    os.close(master)


@pytest.mark.parametrize(
    ("extra", "start"),
    [
        (
            ["--web", "--web-port", "70000"],
            "gaitshift: error: --web-port = 70000 is invalid: allowed a number in [0, 65535]",
        ),
        (["--web-port", "-1"], "gaitshift: error: --web-port = -1 is invalid"),
        (["--teleop"], "gaitshift: error: --teleop = 'stdin' is invalid: allowed a terminal to read the keys from"),
        (["--web", "--teleop"], "gaitshift: error: --teleop = 'stdin' is invalid"),
    ],
    ids=["port-over-65535", "port-negative", "teleop-without-a-terminal", "web-and-teleop-without-a-terminal"],
)
def test_a_bad_live_flag_is_one_line_and_exit_2(cli, monkeypatch, tiny, extra, start):
    monkeypatch.setattr("sys.stdin", io.StringIO("w"))  # not a terminal, even under pytest -s
    code, out, err = cli(["dds", "control", tiny, *extra])
    assert code == 2 and out == "" and err.startswith(start) and err.count("\n") == 1


def test_teleop_on_a_plan_without_live_commands_is_one_line_and_exit_2(cli, tty_stdin):
    code, _, err = cli(["dds", "control", "g1-walk", "--teleop"])
    assert code == 2 and err.count("\n") == 1
    assert err.startswith("gaitshift: error: --teleop = 'g1-walk' is invalid: allowed a live-command scenario")


def fake_controller(live: bool):
    """What live_inputs reads of a controller: its model, and a live plan's limits (or no driver)."""
    from gaitshift.sim.plant import build_plant

    limits = SimpleNamespace(max_speed=(1.0, 0.5, 0.3), max_yaw_rate=0.8)
    driver = SimpleNamespace(gen=SimpleNamespace(p=SimpleNamespace(limits=limits)), command=print) if live else None
    return SimpleNamespace(robot=SimpleNamespace(model=build_plant(0.002, "g1").model), driver=driver)


def test_web_and_teleop_together_feed_the_one_command_input(tty_stdin, tiny):
    check_live_flags(tiny, True, 8080, True)  # --cmd-topic --web --teleop: no conflict
    lines: list[str] = []
    with live_inputs(fake_controller(True), False, (True, free_port()), True, lines.append) as (queues, feed):
        assert [q.name for q in queues] == ["the web page", "the keyboard"] and feed is not None
        assert set(feed.view.sliders) == {"vx", "vy", "yaw"}
        inp = CommandInput(queues, CommandLimits(1.0, 0.5, 0.3, 0.8), lines.append)
        os.write(tty_stdin, b"w")
        deadline = time.monotonic() + 10
        while inp.pending is None and time.monotonic() < deadline:
            time.sleep(0.05)
            inp.poll()
    assert inp.pending is not None and (inp.pending.vx, inp.pending.stop) == (0.1, 0)
    assert "live commands from the web page, the keyboard: vx [-0.5, 1] m/s, |vy| <= 0.3 m/s" in lines[0]
    assert "keys: vx +0.10 m/s, vy +0.00 m/s, yaw_rate +0.00 rad/s" in lines


def test_web_on_a_plan_without_live_commands_is_a_view_without_controls():
    lines: list[str] = []
    with live_inputs(fake_controller(False), False, (True, free_port()), False, lines.append) as (queues, feed):
        assert queues == [] and feed is not None and feed.view.sliders == {}
    assert lines == []
