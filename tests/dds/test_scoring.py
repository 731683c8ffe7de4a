"""The brain's estimate message and its score by the robot process (``gaitshift.dds.diagnostics``,
``gaitshift.dds.scoring``): an estimate is matched to the truth of the LowState_ tick it names; a perfect
estimate scores zero errors and full contact accuracy; the velocity error is taken in each one's heading
frame (a yaw offset alone costs nothing, and shows as yaw drift when it grows), a tilt of known angle
scores that angle, contact flags count per foot; estimates about ticks not kept are unmatched, invalid
ones ignored. The message survives its CDR bytes. And the brain's modules never import the world."""

import ast
import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from gaitshift.common.rotations import tilt_error
from gaitshift.dds.diagnostics import estimate_message
from gaitshift.dds.own_messages import Estimate_
from gaitshift.dds.scoring import EstimateScore, yaw_of

SRC = Path(__file__).resolve().parents[2] / "src"


def quat_zyx(yaw=0.0, pitch=0.0):
    """w x y z of a yaw then a pitch."""
    cy, sy, cp, sp = math.cos(yaw / 2), math.sin(yaw / 2), math.cos(pitch / 2), math.sin(pitch / 2)
    return np.array([cy * cp, -sy * sp, cy * sp, sy * cp])


def record(pos, quat, vel, contact):
    qpos = np.concatenate([pos, quat, np.zeros(29)])
    qvel = np.concatenate([vel, np.zeros(3 + 29)])
    return SimpleNamespace(qpos=qpos, qvel=qvel, contact=np.array(contact, bool))


def truth(score, k, pos, quat, vel, touching):
    score.truth(k, np.concatenate([pos, quat, np.zeros(29)]), np.concatenate([vel, np.zeros(32)]), np.array(touching))


def test_the_estimate_message_survives_its_bytes_and_is_invalid_without_an_estimate():
    rec = record([1.0, 2.0, 0.7], quat_zyx(0.3, 0.1), [0.4, -0.1, 0.02], [True, False])
    msg = Estimate_.deserialize(estimate_message(123, 0.246, "locomotion", rec).serialize())
    assert (msg.tick, msg.t, msg.phase, msg.valid) == (123, 0.246, "locomotion", 1)
    np.testing.assert_allclose(msg.base_quat, quat_zyx(0.3, 0.1))
    np.testing.assert_allclose(msg.base_vel, [0.4, -0.1, 0.02])
    assert list(msg.contact) == [1, 0]
    assert estimate_message(5, 0.0, "stand-up", None).valid == 0


def test_a_perfect_estimate_scores_zero_and_a_yaw_offset_only_drift():
    score = EstimateScore()
    pos, vel = np.array([0.1, 0.0, 0.75]), np.array([0.3, 0.05, 0.0])
    for k in range(10):
        truth(score, k, pos + k * 0.001, quat_zyx(0.0), vel, [True, k % 2 == 0])
    for k in range(10):
        score.add(
            estimate_message(
                k, k * 0.002, "locomotion", record(pos + k * 0.001, quat_zyx(0.0), vel, [True, k % 2 == 0])
            )
        )
    s = score.summary()
    assert (s.estimates_scored, s.estimates_unmatched) == (10, 0)
    assert s.est_velocity_rmse == pytest.approx(0.0, abs=1e-12) and s.est_tilt_rmse == pytest.approx(0.0, abs=1e-7)
    assert s.est_contact_accuracy == 1.0 and s.est_yaw_drift == 0.0 and s.est_position_drift == pytest.approx(0.0)
    # the same motion seen in a frame turned by a growing yaw: the velocity in the heading frame agrees
    score = EstimateScore()
    for k in range(10):
        truth(score, k, pos, quat_zyx(0.0), vel, [True, True])
        yaw = 0.01 * k
        c, s_ = math.cos(yaw), math.sin(yaw)
        turned = np.array([c * vel[0] - s_ * vel[1], s_ * vel[0] + c * vel[1], vel[2]])
        msg = estimate_message(k, 0.0, "locomotion", record(pos, quat_zyx(yaw), turned, [True, False]))
        score.add(Estimate_.deserialize(msg.serialize()))  # off the wire the flags are bytes: counted per foot
    s = score.summary()
    assert s.est_velocity_rmse == pytest.approx(0.0, abs=1e-12)
    assert s.est_yaw_drift == pytest.approx(0.09) and s.est_contact_accuracy == 0.5


def test_a_tilt_scores_its_angle_and_unmatched_or_invalid_estimates_are_counted_apart():
    assert tilt_error(quat_zyx(0.7, 0.05), quat_zyx(-0.2, 0.0)) == pytest.approx(0.05)
    assert yaw_of(quat_zyx(0.7, 0.05)) == pytest.approx(0.7)
    score = EstimateScore(keep=8)
    for k in range(20):
        truth(score, k, [0.0, 0.0, 0.7], quat_zyx(), [0.0, 0.0, 0.0], [True, True])
    score.add(estimate_message(19, 0.0, "locomotion", record([0, 0, 0.72], quat_zyx(0, 0.1), [0.1, 0, 0], [1, 1])))
    score.add(estimate_message(3, 0.0, "locomotion", record([0, 0, 0.7], quat_zyx(), [0, 0, 0], [1, 1])))  # gone
    score.add(estimate_message(18, 0.0, "hold", None))
    s = score.summary()
    assert (s.estimates_received, s.estimates_scored, s.estimates_unmatched) == (3, 1, 1)
    assert s.est_tilt_rmse == pytest.approx(0.1) and s.est_velocity_rmse == pytest.approx(0.1)
    assert s.est_height_rmse == pytest.approx(0.02)


def test_nothing_scored_is_nan():
    s = EstimateScore().summary()
    assert math.isnan(s.est_velocity_rmse) and math.isnan(s.est_contact_accuracy) and math.isnan(s.est_yaw_drift)


def gaitshift_imports(module):
    """The gaitshift modules ``module`` imports (its source read with ast), lazy ones included."""
    tree = ast.parse((SRC / (module.replace(".", "/") + ".py")).read_text())
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("gaitshift"):
            out.add(node.module)
        elif isinstance(node, ast.Import):
            out |= {a.name for a in node.names if a.name.startswith("gaitshift")}
    return out


def test_the_brain_never_imports_the_world_or_the_scoring():
    """The truth lives in the robot process (gaitshift.sim, gaitshift.dds.robot, gaitshift.dds.scoring): none
    of it is reachable from the brain's dds modules."""
    todo, seen = ["gaitshift.dds.brain"], set()
    while todo:
        m = todo.pop()
        if m in seen or not m.startswith("gaitshift.dds"):
            continue
        seen.add(m)
        todo += sorted(gaitshift_imports(m))
    reached = seen | {i for m in seen for i in gaitshift_imports(m)}
    assert "gaitshift.dds.diagnostics" in reached and "gaitshift.dds.cmdvel" in reached
    assert not {m for m in reached if m.startswith("gaitshift.sim")}
    assert not reached & {"gaitshift.dds.robot", "gaitshift.dds.scoring"}
