"""Live velocity commands (``gaitshift.dds.cmdvel``): a command not finite or beyond the live plan's limits, or
a stop flag other than 0/1, is refused with one line naming its field; over DDS (loopback, a fresh domain)
the brain's reader keeps the newest valid command, drops and counts the bad ones (one line each, the first
five), hands a command or a stop to the controller only when asked (a locomotion tick), and refuses what
comes after a stop; a plan that takes no live command is refused for --cmd-topic. ``gaitshift dds cmd``
sends a command a reader receives, and says so in one line when nobody reads; its --teleop turns the keys
of ``gaitshift teleop`` into commands (keys typed on a pseudo-terminal reach a reader on the topic), and
without a terminal is one line, exit 2."""

import io
import math
import os
import pty
import sys
import threading
import time
from types import SimpleNamespace

import pytest

from dds_processes import FakeController
from gaitshift.dds.cmdvel import (
    MAX_LINES,
    CommandInput,
    CommandLimits,
    KeySteer,
    TopicSource,
    check_command,
    live_limits,
    publish,
)
from gaitshift.dds.own_messages import CMD_VEL_TOPIC, VelocityCommand_
from gaitshift.dds.transport import open_endpoint, open_participant, topic_writer
from gaitshift.errors import InputError

LIMITS = CommandLimits(forward=1.0, backward=0.5, sideways=0.3, yaw_rate=0.8)
#: offsets 35, 37, 38 on test_robot_process.py's pid-derived base (test_brain_process.py: 30-32,
#: test_brain_steered.py: 36, test_brain_faults.py: 40-41, test_brain_web.py: 42,
#: test_brain_teleop.py: 43; docs/deploy.md's snippet: 39): within DDS's 232
BASE_DOMAIN = 100 + os.getpid() % 90 + 35


@pytest.mark.parametrize(
    ("fields", "why"),
    [
        ({"vx": math.nan}, "VelocityCommand_.vx = nan is invalid: allowed a number in [-0.5, 1] m/s"),
        ({"vx": 1.2}, "VelocityCommand_.vx = 1.2 is invalid"),
        ({"vx": -0.6}, "VelocityCommand_.vx = -0.6 is invalid"),
        ({"vy": math.inf}, "VelocityCommand_.vy = inf is invalid"),
        ({"yaw_rate": -0.9}, "VelocityCommand_.yaw_rate = -0.9 is invalid: allowed a number in [-0.8, 0.8] rad/s"),
        ({"stop": 2}, "VelocityCommand_.stop = 2 is invalid: allowed 0 or 1"),
    ],
)
def test_a_bad_command_is_refused_naming_its_field(fields, why):
    assert check_command(VelocityCommand_(**fields), LIMITS).startswith(why)


def test_valid_commands_and_a_stop_pass():
    assert check_command(VelocityCommand_(vx=1.0, vy=-0.3, yaw_rate=0.8), LIMITS) == ""
    assert check_command(VelocityCommand_(vx=-0.5), LIMITS) == ""
    assert check_command(VelocityCommand_(vx=math.nan, stop=1), LIMITS) == ""  # a stop ignores the speeds


def test_a_plan_without_live_commands_is_refused_for_the_cmd_topic():
    with pytest.raises(InputError, match="--cmd-topic"):
        live_limits(SimpleNamespace(driver=None), "g1-walk")
    limits = SimpleNamespace(max_speed=(1.1, 0.4, 0.2), max_yaw_rate=0.7)
    live = SimpleNamespace(gen=SimpleNamespace(p=SimpleNamespace(limits=limits)), command=print)
    # a background re-plan's proxy: the host's copy of the driver is ``local``
    assert live_limits(SimpleNamespace(driver=SimpleNamespace(local=live))) == CommandLimits(1.1, 0.4, 0.2, 0.7)


def take_all(inp, n, timeout=10.0):
    """Poll until ``n`` commands were taken (discovery and delivery on the loopback take a moment)."""
    deadline = time.monotonic() + timeout
    while inp.received < n and time.monotonic() < deadline:
        inp.poll()
        time.sleep(0.01)


def test_over_dds_bad_commands_are_dropped_and_counted_the_newest_valid_one_applied():
    domain = BASE_DOMAIN
    lines = []
    inp = CommandInput([TopicSource(open_endpoint(domain, "lo", "controller"))], LIMITS, lines.append)
    sender = open_participant(domain, "lo")
    bad = [VelocityCommand_(seq=i, vx=v) for i, v in enumerate([math.nan, 3.0, -1.0, 0.0, 0.1, 0.2])]
    bad[3].stop = 7
    bad[4].yaw_rate = math.nan
    bad[5].vy = 0.5
    assert publish(sender, VelocityCommand_(seq=10, vx=0.4), repeat=1)  # what ``gaitshift dds cmd`` does
    writer = topic_writer(sender, CMD_VEL_TOPIC, VelocityCommand_)
    for msg in bad:
        writer.write(msg)
    writer.write(VelocityCommand_(seq=11, vx=0.6, yaw_rate=-0.2))
    take_all(inp, 8)
    assert (inp.received, inp.accepted, inp.dropped) == (8, 2, 6)
    assert len(lines) == MAX_LINES and lines[-1].endswith("(further drops only counted)")
    fields = ["vx", "vx", "vx", "stop", "yaw_rate"]
    for line, name in zip(lines, fields, strict=True):
        assert line.startswith(f"gaitshift: dropped rt/gaitshift/cmd_vel: VelocityCommand_.{name} = ")
    assert inp.last_error.startswith("VelocityCommand_.vy = 0.5 is invalid")
    ctrl = FakeController()
    inp.apply(ctrl)
    inp.apply(ctrl)  # nothing new: nothing handed over
    assert ctrl.calls == [("command", 0.6, 0.0, -0.2)] and inp.applied == 1
    # a stop, then a command: the stop is handed over, the command refused
    writer.write(VelocityCommand_(seq=12, stop=1))
    writer.write(VelocityCommand_(seq=13, vx=0.2))
    writer.write(VelocityCommand_(seq=12, stop=1))  # a repeat (gaitshift dds cmd writes --repeat times)
    take_all(inp, 11)
    inp.apply(ctrl)
    assert ctrl.calls[-1] == ("stop",) and inp.stopped and inp.dropped == 7 and inp.accepted == 4
    assert inp.last_error.startswith("VelocityCommand_ after a stop")
    writer.write(VelocityCommand_(seq=12, stop=1))
    take_all(inp, 12)
    inp.apply(ctrl)
    assert ctrl.calls.count(("stop",)) == 1 and inp.dropped == 7  # the stop handed over once


def test_the_cmd_command_sends_one_command_refuses_bad_values_and_says_when_no_brain_listens(cli):
    """``gaitshift dds cmd``: a bad value is one line naming the flag, exit 2; with nobody reading, one line
    and exit 1; with a reader, the command arrives (written --repeat times) and exit 0."""
    code, _, err = cli(["dds", "cmd", "--vx", "nan"])
    assert code == 2 and err.startswith("gaitshift: error: --vx = nan") and err.count("\n") == 1
    domain = BASE_DOMAIN + 2  # 37: free on the shared base (see BASE_DOMAIN)
    code, _, err = cli(["dds", "cmd", "--vx", "0.2", "--domain", str(domain), "--wait", "0.2"])
    assert code == 1 and err.startswith("gaitshift: no reader of rt/gaitshift/cmd_vel") and err.count("\n") == 1
    domain = BASE_DOMAIN + 3
    inp = CommandInput([TopicSource(open_endpoint(domain, "lo", "controller"))], LIMITS, print)
    code, _, err = cli(["dds", "cmd", "--vx", "0.5", "--yaw-rate", "-0.3", "--domain", str(domain), "--repeat", "2"])
    take_all(inp, 2)
    assert code == 0 and err.startswith("sent vx 0.5 m/s, vy 0 m/s, yaw_rate -0.3 rad/s on rt/gaitshift/cmd_vel")
    assert (inp.received, inp.accepted) == (2, 2)
    assert (inp.pending.vx, inp.pending.yaw_rate, inp.pending.stop) == (0.5, -0.3, 0)


def test_keys_steer_by_the_teleop_steps_space_stands_and_q_stops():
    """The keys of ``gaitshift teleop``: 0.1 m/s, 0.05 m/s, 0.2 rad/s a press; space zero; q the stop."""
    keys = KeySteer()
    msgs = [keys.press(a) for a in ("up", "up", "left", "turn-right", "bogus", "stop", "down", "quit")]
    assert msgs[4] is None
    got = [(m.vx, m.vy, m.yaw_rate, m.stop) for m in msgs if m is not None]
    assert got == [
        (0.1, 0.0, 0.0, 0),
        (0.2, 0.0, 0.0, 0),
        (0.2, 0.05, 0.0, 0),
        (0.2, 0.05, -0.2, 0),
        (0.0, 0.0, 0.0, 0),
        (-0.1, 0.0, 0.0, 0),
        (-0.1, 0.0, 0.0, 1),
    ]
    assert [m.seq for m in msgs if m is not None] == list(range(1, 8))
    assert all(check_command(m, LIMITS) == "" for m in msgs if m is not None)


def test_teleop_without_a_terminal_is_one_line_and_exit_2(cli, monkeypatch):
    monkeypatch.setattr("sys.stdin", io.StringIO("w"))  # not a terminal, even under pytest -s
    code, _, err = cli(["dds", "cmd", "--teleop"])
    assert code == 2 and err.startswith("gaitshift: error: --teleop = 'stdin'") and err.count("\n") == 1


def test_teleop_keys_typed_on_a_pty_reach_a_reader_of_the_topic(cli, monkeypatch):
    """``gaitshift dds cmd --teleop`` with stdin a pseudo-terminal: w, d, q are three commands on the topic."""
    domain = BASE_DOMAIN - 1  # 34: free on the shared base (see BASE_DOMAIN)
    inp = CommandInput([TopicSource(open_endpoint(domain, "lo", "controller"))], LIMITS, print)
    master, slave = pty.openpty()
    stdin = os.fdopen(slave, "r")
    monkeypatch.setattr(sys, "stdin", stdin)
    typing = threading.Timer(1.0, os.write, (master, b"wdq"))  # once the key loop reads the terminal
    typing.start()
    try:
        code, out, _ = cli(["dds", "cmd", "--teleop", "--domain", str(domain)])
    finally:
        typing.cancel()
        stdin.close()
        os.close(master)
    take_all(inp, 3)
    lines = [line.split(" (")[0] for line in out.splitlines()]  # " (no brain reading yet)" if discovery lags
    assert code == 0 and lines[:2] == [
        "vx +0.10 m/s, vy +0.00 m/s, yaw_rate +0.00 rad/s",
        "vx +0.10 m/s, vy -0.05 m/s, yaw_rate +0.00 rad/s",
    ]
    assert (inp.received, inp.accepted) == (3, 3) and inp.pending.stop == 1
