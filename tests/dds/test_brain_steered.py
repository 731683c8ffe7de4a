"""The brain steered over DDS and its estimate scored by the robot, between real processes on the loopback
(a fresh pid-derived DDS domain): ``gaitshift dds control --cmd-topic`` on a live scenario that stands until
told otherwise, ``gaitshift dds robot g1``, both in lockstep. Once the brain's own diagnostics
(``rt/gaitshift/estimate``) say it is in locomotion, the test writes on ``rt/gaitshift/cmd_vel`` a NaN
speed and a turn rate beyond the plan's limit (each dropped, counted, one line naming its field), then 0.3
m/s forward, and after 0.8 s of locomotion a stop: the robot walks forward without falling, the plan ends,
exit 0. The robot's summary scores the estimate against its truth (matched by tick). DDS discovery shows
that the brain's participant subscribes to ``rt/lowstate`` and ``rt/gaitshift/cmd_vel`` only, and that the
robot's writes ``rt/lowstate`` only: no truth reaches the brain."""

import json
import os
import signal
import time

from cyclonedds.builtin import BuiltinDataReader, BuiltinTopicDcpsPublication, BuiltinTopicDcpsSubscription

from dds_processes import BRAIN_FLAGS, finish, gaitshift, live_scenario
from gaitshift.dds.own_messages import CLOCK_TOPIC, CMD_VEL_TOPIC, ESTIMATE_TOPIC, Estimate_, VelocityCommand_
from gaitshift.dds.transport import open_participant, topic_reader, topic_writer

#: offset 36 on test_robot_process.py's pid-derived base (see test_cmdvel.py)
DOMAIN = 100 + os.getpid() % 90 + 36
LIVE = live_scenario("steered")


def endpoints(participant, topic):
    """participant key -> the topic names of its readers (or writers), from DDS discovery."""
    out: dict = {}
    for e in BuiltinDataReader(participant, topic).read(N=200):
        out.setdefault(e.participant_key, set()).add(e.topic_name)
    return out


def steer(brain, estimates, writer, loco_ticks=400, timeout=180.0):
    """Watch the brain's estimates; in locomotion write two bad commands and vx 0.3, after ``loco_ticks``
    locomotion ticks a stop. The subscriptions and publications seen meanwhile."""
    seen, sent, stopped, found = 0, False, False, ({}, {})
    deadline = time.monotonic() + timeout
    while brain.poll() is None and time.monotonic() < deadline and not stopped:
        time.sleep(0.02)
        for msg in estimates.take(N=256):
            seen += isinstance(msg, Estimate_) and msg.phase == "locomotion"
        if seen and not sent:
            writer.write(VelocityCommand_(seq=1, vx=float("nan")))
            writer.write(VelocityCommand_(seq=2, vx=0.2, yaw_rate=5.0))
            writer.write(VelocityCommand_(seq=3, vx=0.3))
            sent = True
        if seen >= loco_ticks:
            found = (
                endpoints(writer.participant, BuiltinTopicDcpsSubscription),
                endpoints(writer.participant, BuiltinTopicDcpsPublication),
            )
            writer.write(VelocityCommand_(seq=4, stop=1))
            stopped = True
    return seen, found


def test_the_brain_is_steered_over_dds_and_its_estimate_is_scored_without_the_truth(tmp_path):
    (tmp_path / "live.yaml").write_text(LIVE)
    listener = open_participant(DOMAIN, "lo")
    estimates = topic_reader(listener, ESTIMATE_TOPIC, Estimate_, depth=256)
    writer = topic_writer(listener, CMD_VEL_TOPIC, VelocityCommand_)
    argv = ["dds", "robot", "g1", "--domain", str(DOMAIN), "--lockstep", "--summary", str(tmp_path / "robot.json")]
    robot, rfiles = gaitshift(tmp_path, "robot", *argv)
    flags = [*BRAIN_FLAGS, "--no-warm-up", "--cmd-topic", "--json"]
    brain, bfiles = gaitshift(
        tmp_path, "brain", "dds", "control", str(tmp_path / "live.yaml"), "--domain", str(DOMAIN), *flags
    )
    try:
        seen, (subs, pubs) = steer(brain, estimates, writer)
        finish(brain, bfiles, timeout=180.0)
    finally:
        robot.send_signal(signal.SIGTERM)
        finish(robot, rfiles)
    err = (tmp_path / "brain.err").read_text().strip().splitlines()
    assert brain.returncode == 0, err
    s = json.loads((tmp_path / "brain.out").read_text())
    r = json.loads((tmp_path / "robot.json").read_text())
    assert seen >= 400 and s["phase"] == "stop" and s["reason"] == "the plan ended"
    assert (s["commands_received"], s["commands_dropped"], s["commands_applied"]) == (4, 2, 2)
    drops = [line for line in err if line.startswith("gaitshift: dropped rt/gaitshift/cmd_vel: ")]
    assert [d.split(": ")[2].split(" = ")[0] for d in drops] == ["VelocityCommand_.vx", "VelocityCommand_.yaw_rate"]
    assert s["calibration_samples"] == 100  # --hold 0.2 s
    assert not r["fell"] and r["distance"] > 0.1  # it walked on the command (standing still otherwise)
    # the estimate, scored by the robot on the ticks the brain acted on
    assert r["estimates_scored"] == s["locomotion_ticks"] and r["estimates_unmatched"] == 0
    assert r["est_velocity_rmse"] < 0.05 and r["est_tilt_rmse"] < 0.05 and r["est_contact_accuracy"] > 0.6
    # discovery: the brain reads the state, the lockstep clock (tick counts) and the commands, nothing else;
    # the robot writes the state and its clock only
    brain_key = next(k for k, topics in subs.items() if "rt/lowstate" in topics)
    robot_key = next(k for k, topics in pubs.items() if "rt/lowstate" in topics)
    assert subs[brain_key] == {"rt/lowstate", CLOCK_TOPIC, CMD_VEL_TOPIC}
    assert pubs[brain_key] == {"rt/lowcmd", ESTIMATE_TOPIC}
    assert pubs[robot_key] == {"rt/lowstate", CLOCK_TOPIC}
