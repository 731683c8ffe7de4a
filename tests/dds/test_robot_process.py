"""The robot process ``gaitshift dds robot`` talks the protocol between two real processes on the loopback
(a fresh DDS domain per test, derived from the pytest worker's pid; the loopback configuration sends nothing
elsewhere): in lockstep it answers every command with the next state (tick counting up, the CRC right),
steps once per valid command, drops and counts commands with a bad CRC, and a PD hold of the standing
pose moves the robot as the same hold does in-process without DDS (to float32 rounding); in real time it
holds the world still until the first valid command (the gantry), or damps without commands
(``--no-gantry``), and writes its summary on SIGTERM."""

import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from dds_processes import finish
from gaitshift.control.frames import MotorCommand
from gaitshift.dds.convert import frame_from_lowstate, lowcmd_from_command
from gaitshift.dds.crc import lowstate_crc
from gaitshift.dds.transport import open_endpoint

N = 29
#: each test its own domain: pid-derived base (100..189) plus the test's offset (0..29); the last file's
#: (test_brain_teleop.py, 43) stays within DDS's 232
BASE_DOMAIN = 100 + os.getpid() % 90
#: the gantry test's states after the first valid command
MOVED = 200


def start_robot(domain, tmp_path, *flags):
    summary = tmp_path / "summary.json"
    code = "from gaitshift.cli import main; main()"
    argv = [sys.executable, "-c", code, "dds", "robot", "g1", "--domain", str(domain), "--iface", "lo"]
    log = open(tmp_path / "robot.log", "w")  # noqa: SIM115 (closed with the process)
    env = {**os.environ, "MUJOCO_GL": "egl"}
    proc = subprocess.Popen([*argv, "--summary", str(summary), *flags], stdout=log, stderr=subprocess.STDOUT, env=env)
    return proc, summary, log


def hold(frame, q0):
    """A PD hold of the pose ``q0``: kp 150 N m/rad, kd 4 N m s/rad."""
    return MotorCommand(q=q0, dq=np.zeros(N), kp=np.full(N, 150.0), kd=np.full(N, 4.0), tau=np.zeros(N))


def in_process_distance(n_ticks):
    """The same PD hold in the same world without DDS (targets rounded to float32 as on the wire): the
    pelvis's horizontal displacement, m, after ``n_ticks``."""
    from gaitshift.robots.model import standing_qpos
    from gaitshift.sim.loop import SimOptions
    from gaitshift.sim.plant import build_plant
    from gaitshift.sim.world import World

    plant = build_plant(0.002, "g1")
    qpos0 = standing_qpos(plant)
    world = World(plant, qpos0, SimOptions(noise="none"), False, 1)
    q0 = None
    for k in range(n_ticks):
        world.observe(k)
        frame = world.sense(k)
        q0 = frame.q.astype(np.float32).astype(float) if q0 is None else q0
        world.apply(hold(frame, q0), k)
        world.step()
    return float(np.linalg.norm(world.d.qpos[:2] - qpos0[:2]))


def test_lockstep_answers_each_command_counts_bad_crcs_and_holds_the_robot_up(tmp_path):
    domain = BASE_DOMAIN + 0
    controller = open_endpoint(domain, "lo", "controller")
    proc, summary_path, log = start_robot(domain, tmp_path, "--lockstep", "--duration", "0.2")
    ticks, q0, bad_sent, good_sent = [], None, 0, 0
    deadline = time.monotonic() + 90.0
    try:
        while proc.poll() is None and time.monotonic() < deadline:
            if not controller.wait(0.05):
                continue
            for state in controller.take():
                assert state.crc == lowstate_crc(state)
                frame = frame_from_lowstate(state, state.tick * 0.002, N)
                q0 = frame.q if q0 is None else q0
                ticks.append(state.tick)
                cmd = lowcmd_from_command(hold(frame, q0), state.mode_machine)
                if bad_sent < 5 and state.tick >= 10 and state.tick % 10 == 0 and ticks.count(state.tick) == 1:
                    cmd.crc ^= 0x5A5A  # corrupted: the robot must drop it and keep waiting
                    controller.writer.write(cmd)
                    bad_sent += 1
                    continue
                controller.writer.write(cmd)
                good_sent += 1
    finally:
        finish(proc, [log], timeout=60.0)
    assert proc.returncode == 0, (tmp_path / "robot.log").read_text()
    s = json.loads(summary_path.read_text())
    assert s["ticks"] == 100 and s["sim_time"] == pytest.approx(0.2)
    assert s["crc_rejects"] == bad_sent == 5 and s["packets_dropped"] == 5
    # every tick needs a valid command; an answer to a repeated state may be one more, or lost before matching
    assert 100 + 5 <= s["packets_received"] <= good_sent + bad_sent
    assert s["commands_applied"] == 100 and s["damping_ticks"] == 0
    assert not s["fell"]
    # the protocol adds nothing but float32 rounding: the run matches the in-process one
    assert s["distance"] == pytest.approx(in_process_distance(100), abs=1e-6)
    assert sorted(set(ticks)) == list(range(100))  # one state per tick, each answered


def test_real_time_damps_without_commands_and_writes_the_summary_on_sigterm(tmp_path):
    domain = BASE_DOMAIN + 1
    controller = open_endpoint(domain, "lo", "controller")
    proc, summary_path, log = start_robot(domain, tmp_path, "--damping-kd", "3", "--no-gantry")
    seen = 0
    deadline = time.monotonic() + 60.0
    try:
        while seen < 50 and proc.poll() is None and time.monotonic() < deadline:
            if controller.wait(0.05):
                seen += len(controller.take())
        bad = lowcmd_from_command(MotorCommand.torque(np.zeros(N)), 0)
        bad.crc ^= 1
        for _ in range(3):
            controller.writer.write(bad)
        time.sleep(0.5)
        proc.send_signal(signal.SIGTERM)
    finally:
        finish(proc, [log], timeout=60.0)
    assert seen >= 50
    assert proc.returncode == 0, (tmp_path / "robot.log").read_text()
    s = json.loads(summary_path.read_text())
    assert s["stopped_by"] == "SIGTERM"
    assert s["crc_rejects"] == s["packets_received"] == 3 and s["commands_applied"] == 0
    assert s["damping_ticks"] == s["ticks"] >= 50 and s["states_published"] >= s["ticks"]


def test_the_gantry_holds_the_world_still_until_the_first_valid_command(tmp_path):
    """Held: the same joint angles tick after tick, then the legs fold on zero torque. Its recording (a
    SIGTERM ends the run) has a row per tick, the held ones marked 0 with no command, the others the zero
    torque applied, and the truth of the held ticks unchanged."""
    domain = BASE_DOMAIN + 2
    controller = open_endpoint(domain, "lo", "controller")
    # the loop below answers each state from Python on shared cores: a stall past the default 0.1 s would
    # damp (66 ticks once, in a full suite on a slow machine); the damping itself is the test above's
    flags = ("--record", str(tmp_path / "robot.npz"), "--damping-after", "1.0")
    proc, summary_path, log = start_robot(domain, tmp_path, *flags)
    # ``moved``: the states published after the first valid command was sent (a stalled take brings
    # held states queued behind it); of MOVED such states at least half were driven by a command unless
    # the link stalled for MOVED / 2 ticks
    held, moved, first = [], [], None
    deadline = time.monotonic() + 60.0
    try:
        while len(moved) < MOVED and proc.poll() is None and time.monotonic() < deadline:
            if not controller.wait(0.05):
                continue
            for state in controller.take():  # a take may bring several states: stop at the last moved
                if len(moved) == MOVED:
                    break
                frame = frame_from_lowstate(state, state.tick * 0.002, N)
                if len(held) < 50:  # no command yet, then a corrupt one: the world must not move
                    held.append(frame.q)
                    bad = lowcmd_from_command(MotorCommand.torque(np.zeros(N)), 0)
                    bad.crc ^= 1
                    controller.writer.write(bad)
                    continue
                if first is not None and state.tick > first:
                    moved.append(frame.q)
                first = state.tick if first is None else first
                controller.writer.write(lowcmd_from_command(MotorCommand.torque(np.zeros(N)), state.mode_machine))
        proc.send_signal(signal.SIGTERM)
    finally:
        finish(proc, [log], timeout=60.0)
    assert proc.returncode == 0, (tmp_path / "robot.log").read_text()
    assert len(held) == 50 and len(moved) == MOVED
    assert np.ptp(np.array(held), axis=0).max() == 0.0  # held: the same joint angles, tick after tick
    assert np.ptp(np.array(moved), axis=0).max() > 1e-3  # zero torque after it: the legs fold
    s = json.loads(summary_path.read_text())
    assert s["held_ticks"] >= 50 and s["commands_applied"] >= MOVED // 2 and s["damping_ticks"] == 0
    assert s["held_ticks"] + s["commands_applied"] == s["ticks"]
    r = np.load(tmp_path / "robot.npz")
    assert len(r["tick"]) == s["ticks"] and np.array_equal(r["tick"], np.arange(s["ticks"]))
    assert (r["applied"] == 0).sum() == s["held_ticks"] and (r["applied"] == 1).sum() == s["commands_applied"]
    assert not r["cmd_kd"][r["applied"] == 0].any() and not r["cmd_tau"].any()
    assert np.ptp(r["qpos"][r["applied"] == 0], axis=0).max() == 0.0
