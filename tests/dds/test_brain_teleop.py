"""The brain steered by the keys (``gaitshift dds control --teleop``) between real processes on the loopback
(a fresh pid-derived DDS domain, lockstep), its stdin a pseudo-terminal: no real terminal needed. Once the
brain's diagnostics say it is in locomotion, the test types ``www`` (0.3 m/s forward) on the pty and, 0.8 s
of locomotion later, ``q`` (the stop): each key is a line of the brain's, the robot walks forward without
falling, the plan ends, exit 0 with the four commands applied and none dropped, and the brain leaves the
terminal in the modes it found it in."""

import json
import os
import pty
import signal
import subprocess
import sys
import termios
import time

from dds_processes import BRAIN_FLAGS, finish, gaitshift, live_scenario
from gaitshift.dds.own_messages import ESTIMATE_TOPIC, Estimate_
from gaitshift.dds.transport import open_participant, topic_reader

#: offset 43 on test_robot_process.py's pid-derived base (see test_cmdvel.py): the last within DDS's 232
DOMAIN = 100 + os.getpid() % 90 + 43
LIVE = live_scenario("key-steered")


def test_the_keys_on_a_pty_steer_the_brain_between_real_processes(tmp_path):
    (tmp_path / "live.yaml").write_text(LIVE)
    estimates = topic_reader(open_participant(DOMAIN, "lo"), ESTIMATE_TOPIC, Estimate_, depth=256)
    master, slave = pty.openpty()
    before = termios.tcgetattr(slave)
    argv = ["dds", "robot", "g1", "--domain", str(DOMAIN), "--lockstep", "--summary", str(tmp_path / "robot.json")]
    robot, rfiles = gaitshift(tmp_path, "robot", *argv)
    flags = [*BRAIN_FLAGS, "--no-warm-up", "--teleop", "--json"]
    code = "from gaitshift.cli import main; main()"
    out, err = open(tmp_path / "brain.out", "w"), open(tmp_path / "brain.err", "w")  # noqa: SIM115
    brain = subprocess.Popen(
        [sys.executable, "-c", code, "dds", "control", str(tmp_path / "live.yaml"), "--domain", str(DOMAIN), *flags],
        stdin=slave,
        stdout=out,
        stderr=err,
        env={**os.environ, "MUJOCO_GL": "egl"},
    )
    try:
        seen, typed = 0, False
        deadline = time.monotonic() + 120
        while brain.poll() is None and time.monotonic() < deadline and seen < 400:
            time.sleep(0.02)
            seen += sum(isinstance(m, Estimate_) and m.phase == "locomotion" for m in estimates.take(N=256))
            if seen and not typed:
                os.write(master, b"www")
                typed = True
        os.write(master, b"q")
        finish(brain, (out, err), timeout=60.0)
        after = termios.tcgetattr(slave)
    finally:
        robot.send_signal(signal.SIGTERM)
        finish(robot, rfiles)
        if brain.poll() is None:
            finish(brain, (out, err), timeout=0.1)
        os.close(master)
        os.close(slave)
    lines = (tmp_path / "brain.err").read_text()
    assert brain.returncode == 0, lines[-2000:]
    s = json.loads((tmp_path / "brain.out").read_text())
    r = json.loads((tmp_path / "robot.json").read_text())
    assert seen >= 400 and s["phase"] == "stop" and s["reason"] == "the plan ended"
    assert (s["commands_received"], s["commands_dropped"]) == (4, 0) and s["commands_applied"] >= 2
    assert "live commands from the keyboard: vx [" in lines and "keys: vx +0.30 m/s" in lines and "keys: stop" in lines
    assert not r["fell"] and r["distance"] > 0.1  # it walked on the keys (standing otherwise)
    assert after == before  # the terminal's modes restored
