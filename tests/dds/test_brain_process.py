"""The brain ``gaitshift dds control`` and the robot process ``gaitshift dds robot g1`` as two real processes on
the loopback, both in lockstep (a fresh DDS domain per test, derived from the pytest worker's pid as in
test_robot_process.py; the loopback configuration sends nothing elsewhere). On a tiny scenario (stand, walk
0.2 m/s for 0.5 s, stop) the brain damps, stands the robot up, walks it and stops: exit 0, the robot did not
fall, the pelvis moved forward as far as the plan within 5 cm, the last command the robot received is
damping, the hold's gyro readings calibrated the controller, and the robot scored every estimate. With
the robot killed mid-run the brain finds the state stale, writes damping and exits 1 with one line saying so;
with no robot at all it says so in one line and exits 1; domain 0 without --real-robot is refused (exit 2)
before any DDS traffic, as is a flag out of its range."""

import json
import os
import signal
import time

import numpy as np
import pytest

from dds_processes import BRAIN_FLAGS, TINY, finish, gaitshift
from gaitshift.dds.transport import open_endpoint

#: offsets 30.. past test_robot_process.py's (0..29) on the same pid-derived base
BASE_DOMAIN = 100 + os.getpid() % 90 + 30


def start_pair(tmp_path, domain, *extra, link=()):
    """The robot process (with the ``link`` flags: its faults, its recording) and the brain (with ``extra`` flags)
    on ``domain``."""
    (tmp_path / "tiny.yaml").write_text(TINY)
    summary = str(tmp_path / "robot.json")
    robot = gaitshift(
        tmp_path, "robot", "dds", "robot", "g1", "--domain", str(domain), "--lockstep", "--summary", summary, *link
    )
    brain = gaitshift(
        tmp_path,
        "brain",
        "dds",
        "control",
        str(tmp_path / "tiny.yaml"),
        "--domain",
        str(domain),
        "--json",
        *BRAIN_FLAGS,
        *extra,
    )
    return robot, brain


def last_command(listener):
    """The newest rt/lowcmd the listener holds (its reader keeps the last 64)."""
    cmds = listener.reader.take(N=64)
    assert cmds, "no rt/lowcmd seen"
    return cmds[-1]


def is_damping(msg, n=29):
    return all(m.mode == 1 and m.kp == 0 and m.kd > 0 and m.tau == 0 for m in msg.motor_cmd[:n])


def test_the_brain_stands_the_robot_up_walks_the_plan_and_ends_in_damping(tmp_path):
    """Exit 0, no fall, the distance of the plan within 5 cm, the last command damping. Both record the
    run (--record), and the recordings meet at the robot's tick (check_recordings)."""
    domain = BASE_DOMAIN
    listener = open_endpoint(domain, "lo", "robot")  # reads rt/lowcmd, writes nothing
    recordings = tmp_path / "brain.npz", tmp_path / "robot.npz"
    (robot, rfiles), (brain, bfiles) = start_pair(
        tmp_path, domain, "--record", str(recordings[0]), link=("--record", str(recordings[1]))
    )
    try:
        finish(brain, bfiles, timeout=240.0)
        cmd = last_command(listener)
    finally:
        robot.send_signal(signal.SIGTERM)
        finish(robot, rfiles)
    err = (tmp_path / "brain.err").read_text()
    assert brain.returncode == 0, err
    s = json.loads((tmp_path / "brain.out").read_text())
    r = json.loads((tmp_path / "robot.json").read_text())
    assert s["phase"] == "stop" and s["reason"] == "the plan ended" and s["locomotion_ticks"] > 500
    assert not r["fell"], r
    assert r["distance"] == pytest.approx(s["planned_distance"], abs=0.05)
    assert s["planned_distance"] > 0.15
    assert is_damping(cmd)
    for key in ("tick_p50_ms", "tick_p99_ms", "tick_p999_ms", "missed_deadlines"):
        assert np.isfinite(s[key])
    # the hold's 100 gyro samples calibrated the controller; the robot scored every controller tick's estimate
    assert s["calibration_samples"] == 100 and s["estimates_written"] == s["ticks"]
    assert r["estimates_scored"] == s["locomotion_ticks"] and r["estimates_unmatched"] == 0
    assert r["est_velocity_rmse"] < 0.05 and abs(r["est_yaw_drift"]) < 0.02
    # the estimator starts from the pose the stand-up left (its tilt from the soles, not the plan's: 0.03 rad
    # off) and the score reads the contact flags per foot: 0.0007 rad and 0.986 measured
    assert r["est_tilt_rmse"] < 0.005 and r["est_contact_accuracy"] > 0.95
    check_recordings(*recordings, s, r)


def check_recordings(brain_file, robot_file, s, r_summary):
    """The two recordings meet at the robot's tick (gaitshift.dds.record): the joint angles the brain
    recorded for the state of tick k are the robot's truth at tick k (noise none: to float32's rounding of
    LowState_), the command the robot applied at tick k is the one the brain wrote for that state (lockstep:
    a command answers its tick's state), and the brain's own columns agree with its summary (every tick's
    duration, the missed deadlines, the controller's ticks). No value is NaN. The two files alone give the
    robot's score of the estimate (scored live from rt/gaitshift/estimate) back: the same estimates, ticks
    and truth by another road."""
    from gaitshift.dds.record import meet
    from gaitshift.robots import load_robot

    b, r = np.load(brain_file), np.load(robot_file)
    meta = json.loads(str(b["meta"]))
    assert meta["rows"] == s["ticks"] and all(np.all(np.isfinite(b[k])) for k in meta["columns"])
    m = load_robot("g1").model()
    adr = [int(m.joint(name).qposadr[0]) for name in meta["motors"]]
    rows = meet(b, r)
    assert (rows >= 0).all()
    assert np.abs(b["q"] - r["qpos"][rows][:, adr]).max() < 1e-6
    applied = r["applied"][rows] == 1
    assert applied.sum() > 0.9 * len(rows)
    for key in ("cmd_q", "cmd_dq", "cmd_kp", "cmd_kd", "cmd_tau"):
        assert np.abs(b[key][applied] - r[key][rows][applied]).max() < 1e-4 * max(1.0, np.abs(b[key]).max())
    assert np.percentile(b["duration"], 50) * 1e3 == pytest.approx(s["tick_p50_ms"], rel=1e-9)
    assert b["missed"].sum() == s["missed_deadlines"] and b["estimated"].sum() == s["locomotion_ticks"]
    from gaitshift.dds.scoring import score_recordings

    score = score_recordings(b, r)
    assert score.estimates_scored == r_summary["estimates_scored"] and score.estimates_unmatched == 0
    for key in ("est_velocity_rmse", "est_tilt_rmse", "est_height_rmse", "est_contact_accuracy", "est_yaw_drift"):
        assert getattr(score, key) == pytest.approx(r_summary[key], rel=1e-9, abs=1e-12), key


def test_a_lossy_late_link_still_walks_the_plan(tmp_path):
    """The robot's link loses 5 % of the states, corrupts 1 % and delays each by 4 +- 1 ms: the brain bridges
    the missing ticks and walks the plan's distance within 5 cm without a fall; every corrupted state is one
    the brain dropped for its CRC, and the delays are the asked ones in ticks. Where the delay shrank by a
    tick, two states came due at one tick: the controller measures the older and acts on the newer. The brain
    ticks once per robot tick, as in real time, on the state it holds when none came (the robot's clock,
    gaitshift.dds.lockstep): only the ticks before the first state arrived go without it."""
    domain = BASE_DOMAIN + 3
    faults = ["--drop", "0.05", "--corrupt", "0.01", "--delay-ms", "4", "--jitter-ms", "1", "--seed", "2"]
    robot, brain = start_pair(tmp_path, domain, link=faults)
    try:
        finish(*brain, timeout=240.0)
    finally:
        robot[0].send_signal(signal.SIGTERM)
        finish(*robot)
    assert brain[0].returncode == 0, (tmp_path / "brain.err").read_text()
    s = json.loads((tmp_path / "brain.out").read_text())
    r = json.loads((tmp_path / "robot.json").read_text())
    assert not r["fell"], r
    assert r["distance"] == pytest.approx(s["planned_distance"], abs=0.05)
    assert r["link_dropped"] > 0.02 * r["ticks"] and r["link_corrupted"] > 0
    assert s["states_dropped"] == r["link_corrupted"]
    assert 2.0 <= r["link_delay_ticks_mean"] <= 3.0 and r["link_delay_ticks_max"] == 3
    assert s["states_measured_only"] > 0
    assert 0 <= r["ticks"] - s["ticks"] <= r["link_delay_ticks_max"] + 1, (r["ticks"], s["ticks"])


def test_the_robot_killed_mid_run_sends_the_brain_to_damping_and_exit_1(tmp_path):
    """The robot process killed during the stand-up: the brain's next state is stale, it writes damping
    and exits 1 with one line naming the stale state."""
    domain = BASE_DOMAIN + 1
    listener = open_endpoint(domain, "lo", "robot")  # reads rt/lowcmd, writes nothing
    (robot, rfiles), (brain, bfiles) = start_pair(tmp_path, domain, "--no-warm-up")
    try:
        deadline, seen = time.monotonic() + 120.0, 0
        while seen < 60 and time.monotonic() < deadline and brain.poll() is None:
            if listener.wait(0.1):
                seen += len(listener.reader.take(N=64))
        robot.kill()
        finish(robot, rfiles)
        finish(brain, bfiles)
        cmd = last_command(listener)
    finally:
        if robot.poll() is None:
            robot.kill()
    assert seen >= 60
    err = (tmp_path / "brain.err").read_text().strip().splitlines()
    assert brain.returncode == 1
    assert err[-1].startswith("gaitshift: fault: state stale: the newest rt/lowstate is"), err
    s = json.loads((tmp_path / "brain.out").read_text())
    assert s["phase"] == "fault" and s["exit_code"] == 1
    assert is_damping(cmd)


def test_no_robot_is_one_line_and_exit_1(tmp_path):
    """Nobody publishes rt/lowstate: after --state-timeout one line names the domain and the interface."""
    (tmp_path / "tiny.yaml").write_text(TINY)
    brain, files = gaitshift(
        tmp_path,
        "brain",
        "dds",
        "control",
        str(tmp_path / "tiny.yaml"),
        "--domain",
        str(BASE_DOMAIN + 2),
        "--state-timeout",
        "0.3",
        "--no-warm-up",
    )
    finish(brain, files)
    err = (tmp_path / "brain.err").read_text().strip().splitlines()
    assert brain.returncode == 1
    assert err[-1] == (
        f"gaitshift: damping: no rt/lowstate from the robot within 0.3 s on DDS domain {BASE_DOMAIN + 2} "
        "over lo: is the robot process running?"
    )


@pytest.mark.parametrize(
    ("flags", "name"),
    [
        (["--domain", "0"], "--domain"),
        (["--stale-limit", "0"], "--stale-limit"),
        (["--tilt-limit", "3"], "--tilt-limit"),
        (["--standup-time", "0"], "--standup-time"),
        (["--state-timeout", "-1"], "--state-timeout"),
        (["--hold", "-0.1"], "--hold"),
        (["--diag-every", "-1"], "--diag-every"),
        (["--latency", "51"], "--latency"),
        (["--deadline", "0.5"], "--deadline"),
        (["--rt-priority", "0"], "--rt-priority"),
        (["--cmd-topic"], "--cmd-topic"),  # g1-walk's plan is fixed: no live command
        (["--record", "run.csv"], "--record"),
        (["--record", "/"], "--record"),
    ],
)
def test_a_bad_flag_or_domain_0_without_the_real_robot_flag_is_one_line_and_exit_2(cli, flags, name):
    """Refused before any controller is built or DDS opened: one line naming the flag, exit 2 (domain 0, a
    real robot's, needs --real-robot)."""
    code, _, err = cli(["dds", "control", "g1-walk", *flags])
    assert code == 2 and err.startswith(f"gaitshift: error: {name} = ") and err.count("\n") == 1


@pytest.mark.parametrize(("known", "floor"), [(True, 0.0), (False, None)])
def test_the_brain_tells_its_estimator_the_flat_floor_when_told_it_is_known(known, floor):
    from gaitshift.dds.brain import BrainOptions
    from gaitshift.dds.brain_setup import build_controller

    ctrl = build_controller(BrainOptions("g1-walk", known_floor=known, replan="inline"))
    assert ctrl.state.estimator is not None
    assert ctrl.state.estimator.filter.floor == floor
