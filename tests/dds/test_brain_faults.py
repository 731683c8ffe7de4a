"""The brain process against a scripted robot in the test (lockstep on the loopback, a fresh DDS domain per
test): a state with a NaN joint angle is a fault (damping, exit 1, one line naming the field); states
with a bad CRC are dropped and counted, not faults; and with ``--real-robot`` a robot whose motors hold
torque at start is refused (exit 1, one line) before any command is written."""

import json
import os
import subprocess
import sys
import time

import numpy as np

from dds_processes import finish
from gaitshift.control.frames import SensorFrame
from gaitshift.dds.convert import lowstate_from_frame
from gaitshift.dds.crc import lowstate_crc
from gaitshift.dds.own_messages import CLOCK_TOPIC, Clock_
from gaitshift.dds.transport import open_endpoint, topic_writer

N = 29
#: offsets 40.. past test_robot_process.py's and test_brain_process.py's on the same pid-derived base
BASE_DOMAIN = 100 + os.getpid() % 90 + 40
SCENARIO = "planner: locomotion\nrobot: g1\ngait: walk\ncommands: [{t: 0.0, vx: 0.2}]\nstop_at: 0.5\n"


def brain(tmp_path, domain, *flags):
    (tmp_path / "s.yaml").write_text(SCENARIO)
    code = "from gaitshift.cli import main; main()"
    argv = ["dds", "control", str(tmp_path / "s.yaml"), "--domain", str(domain), "--lockstep", "--no-warm-up"]
    out, err = open(tmp_path / "out", "w"), open(tmp_path / "err", "w")  # noqa: SIM115
    env = {**os.environ, "MUJOCO_GL": "egl"}
    argv += ["--stale-limit", "0.5", "--json", *flags]
    return subprocess.Popen([sys.executable, "-c", code, *argv], stdout=out, stderr=err, env=env), (out, err)


def state(k, tau=0.0):
    """A level robot at rest, every joint at 0 rad (inside every G1 range), ``tau`` N m on every motor."""
    frame = SensorFrame(
        t=0.0,
        imu_quat=np.array([1.0, 0.0, 0.0, 0.0]),
        imu_gyro=np.zeros(3),
        imu_acc=np.array([0.0, 0.0, 9.81]),
        q=np.zeros(N),
        dq=np.zeros(N),
        tau_est=np.full(N, tau),
    )
    return lowstate_from_frame(frame, k, 0)


def script(proc, robot, make, timeout=90.0):
    """Answer each command with the next states ``make(k)`` (a list, written in order) and the lockstep
    clock of tick ``k`` naming state ``k`` (gaitshift.dds.lockstep) until the brain exits; the commands
    received."""
    k, commands, deadline = 0, [], time.monotonic() + timeout
    clock = topic_writer(robot, CLOCK_TOPIC, Clock_)

    def send(k):
        for m in make(k):
            robot.writer.write(m)
        clock.write(Clock_(tick=k, state_tick=k))

    send(0)
    while proc.poll() is None and time.monotonic() < deadline:
        if not robot.wait(0.05):
            send(k)  # not seen yet (discovery): again
            continue
        got = robot.take()
        commands += got
        if got:
            k += 1
            send(k)
    return commands


def test_a_nan_in_the_state_is_a_fault_and_bad_crcs_are_dropped(tmp_path):
    """States 3-5 each preceded by a copy with a wrong CRC: the copies dropped and counted, the run goes on.
    State 20 with q[3] = NaN: damping from that tick, exit 1, the line names LowState_.motor_state.q[3]."""
    domain = BASE_DOMAIN
    robot = open_endpoint(domain, "lo", "robot")
    proc, files = brain(tmp_path, domain)

    def make(k):
        msg = state(k)
        if k == 20:
            msg.motor_state[3].q = float("nan")
            msg.crc = lowstate_crc(msg)
        if 3 <= k <= 5:  # a corrupted copy first
            bad = state(k)
            bad.crc ^= 1
            return [bad, msg]
        return [msg]

    try:
        commands = script(proc, robot, make)
    finally:
        finish(proc, files, timeout=60.0)
    err = (tmp_path / "err").read_text().strip().splitlines()
    assert proc.returncode == 1, err
    assert err[-1].startswith("gaitshift: fault: state out of range: LowState_.motor_state.q[3] = nan"), err
    s = json.loads((tmp_path / "out").read_text())
    assert s["phase"] == "fault" and s["states_dropped"] >= 3
    assert all(m.kp == 0 and m.kd > 0 for m in commands[-1].motor_cmd[:N])


def test_a_real_robot_holding_torque_at_start_is_refused(tmp_path):
    """--real-robot and every motor enabled with 5 N m: one line, exit 1, no command written."""
    domain = BASE_DOMAIN + 1
    robot = open_endpoint(domain, "lo", "robot")
    proc, files = brain(tmp_path, domain, "--real-robot")
    try:
        commands = script(proc, robot, lambda k: [state(k, tau=5.0)])
    finally:
        finish(proc, files, timeout=60.0)
    err = (tmp_path / "err").read_text().strip().splitlines()
    assert proc.returncode == 1
    assert err[-1].startswith("gaitshift: damping: refused: the robot is not damping or zero-torque"), err
    assert commands == []
