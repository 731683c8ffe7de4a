"""The brain's safety state machine (``gaitshift.dds.safety``) alone, without DDS or a controller: it goes
damping -> stand-up -> (hold) -> locomotion -> stop -> damping in that order and at the set times, the hold
holding the start pose; the stand-up's
targets run from the measured pose to the start pose with zero speed at both ends, and a joint driven by
its PD command reaches the start pose; every fault (a stale state, a non-finite or out-of-range value, a
joint beyond its range, a tilt beyond the limit, a non-finite command or a negative gain) sends it to
damping with one line naming the cause, for good; every command is clamped to the joint range, the speed
limit and the torque limit at the measured state. And a real robot is taken over only when it damps."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from gaitshift.control.frames import MotorCommand, SensorFrame
from gaitshift.dds.brain_setup import passive_at_start
from gaitshift.dds.safety import Limits, Safety, SafetySettings, standup_gains, tilt_angle

N = 3
LIMITS = Limits(
    q_low=np.array([-1.0, -2.0, 0.0]),
    q_high=np.array([1.0, 2.0, 2.5]),
    dq_max=np.array([20.0, 20.0, 30.0]),
    tau_max=np.array([50.0, 80.0, 100.0]),
)
START = np.array([0.2, -0.3, 1.0])


def machine(**kw):
    kp, kd = standup_gains(LIMITS.tau_max)
    settings = SafetySettings(kp, kd, **({"damping_time": 0.1, "standup_time": 1.0, "stale": 0.02} | kw))
    return Safety(LIMITS, settings, START)


def frame(q=(0.0, 0.0, 0.5), dq=(0.0, 0.0, 0.0), quat=(1.0, 0.0, 0.0, 0.0), t=0.0):
    return SensorFrame(
        t=t,
        imu_quat=np.array(quat, float),
        imu_gyro=np.zeros(3),
        imu_acc=np.array([0.0, 0.0, 9.81]),
        q=np.array(q, float),
        dq=np.array(dq, float),
        tau_est=np.zeros(N),
    )


def is_damping(cmd, kd=2.0):
    return np.all(cmd.kp == 0) and np.all(cmd.kd == kd) and np.all(cmd.tau == 0)


def test_phases_in_order_damping_standup_locomotion_stop_damping():
    """Damping for damping_time, the stand-up for standup_time, then locomotion (None: the host ticks its
    controller) until stop, then damping for good."""
    s = machine()
    seen = []
    for k in range(200):
        t = k * 0.01
        if k == 150:
            s.stop(t)
        cmd = s.step(t, frame(), 0.0)
        seen.append(s.phase)
        if s.phase in ("damping", "stop"):
            assert is_damping(cmd)
        if s.phase == "locomotion":
            assert cmd is None
    order = [p for i, p in enumerate(seen) if i == 0 or seen[i - 1] != p]
    assert order == ["damping", "stand-up", "locomotion", "stop"]
    assert seen.index("stand-up") == 10 and seen.index("locomotion") == 110
    assert s.locomotion_start == pytest.approx(1.1) and s.reason == "the plan ended"


def test_the_hold_comes_between_the_standup_and_locomotion_and_holds_the_start_pose():
    """With hold_time 0.3 s: damping, stand-up, hold (the start pose at zero speed with the stand-up's gains,
    every tick of it), then locomotion, whose clock starts when the hold ends."""
    s = machine(hold_time=0.3)
    seen = []
    for k in range(200):
        cmd = s.step(k * 0.01, frame(), 0.0)
        seen.append(s.phase)
        if s.phase == "hold":
            np.testing.assert_allclose(cmd.q, START)
            np.testing.assert_allclose(cmd.dq, 0.0)
            np.testing.assert_allclose(cmd.kp, s.settings.standup_kp)
    order = [p for i, p in enumerate(seen) if i == 0 or seen[i - 1] != p]
    assert order == ["damping", "stand-up", "hold", "locomotion"]
    assert seen.index("hold") == 110 and seen.index("locomotion") == 140 and seen.count("hold") == 30
    assert s.locomotion_start == pytest.approx(1.4)


def test_standup_targets_run_from_the_measured_pose_to_the_start_pose_and_a_pd_joint_gets_there():
    """The targets start at the pose measured when the stand-up begins and end at the start pose, target
    speed zero at both ends; unit-inertia joints under the commands (no gravity) end within 1 mrad of it."""
    s = machine(damping_time=0.0)
    q, dq, dt = np.array([0.0, 0.0, 0.5]), np.zeros(N), 0.002
    first = None
    for k in range(int(1.0 / dt)):
        cmd = s.step(k * dt, frame(q, dq), 0.0)
        assert s.phase == "stand-up"
        first = cmd if first is None else first
        tau = cmd.tau + cmd.kp * (cmd.q - q) + cmd.kd * (cmd.dq - dq)
        dq = dq + dt * tau / 1.0
        q = q + dt * dq
    np.testing.assert_allclose(first.q, [0.0, 0.0, 0.5])
    np.testing.assert_allclose(first.dq, 0.0)
    last = s.standup_command(1.0 - 1e-9)
    np.testing.assert_allclose(last.q, START, atol=1e-6)
    for _ in range(1500):  # the final target held 3 s (the lightly damped unit-inertia joints settle)
        cmd = s.guard(s.standup_command(s.since + 1.0), frame(q, dq), 2.0)
        tau = cmd.tau + cmd.kp * (cmd.q - q) + cmd.kd * (cmd.dq - dq)
        dq = dq + dt * tau
        q = q + dt * dq
    np.testing.assert_allclose(q, START, atol=1e-3)
    assert s.step(1.0, frame(q, dq), 0.0) is None and s.phase == "locomotion"


@pytest.mark.parametrize(
    ("state", "age", "cause"),
    [
        ({}, 0.05, "state stale"),
        ({"q": (math.nan, 0.0, 0.5)}, 0.0, "state out of range: q[0] is not finite"),
        ({"dq": (0.0, 31.0, 0.0)}, 0.0, "state out of range: motor 1 speed"),
        ({"quat": (0.8, 0.0, 0.0, 0.0)}, 0.0, "state out of range: |imu_quat|"),
        ({"q": (0.0, 0.0, 2.6)}, 0.0, "joint limit: motor 2 at 2.600 rad"),
        ({"quat": (math.cos(0.35), math.sin(0.35), 0.0, 0.0)}, 0.0, "fall: the pelvis is tilted 0.70 rad"),
    ],
)
def test_each_state_fault_sends_it_to_damping_with_its_reason_for_good(state, age, cause):
    """A bad state in any phase (here in the stand-up) is a fault: damping now and later, the reason kept."""
    s = machine()
    s.step(0.0, frame(), 0.0)
    s.step(0.2, frame(), 0.0)
    assert s.phase == "stand-up"
    cmd = s.step(0.21, frame(**state), age)
    assert s.phase == "fault" and s.reason.startswith(cause) and "\n" not in s.reason
    assert is_damping(cmd)
    assert is_damping(s.step(5.0, frame(), 0.0)) and s.phase == "fault" and s.reason.startswith(cause)


def test_a_tilt_within_the_limit_is_no_fault():
    """0.5 rad of tilt with the limit at 0.6 rad passes; the tilt is the angle of the body's z axis."""
    q = (math.cos(0.25), 0.0, math.sin(0.25), 0.0)
    assert tilt_angle(np.array(q)) == pytest.approx(0.5)
    assert machine().check_state(frame(quat=q), 0.0) == ""


@pytest.mark.parametrize(
    ("field", "value", "cause"),
    [("tau", math.nan, "command out of range: tau[1] is not finite"), ("kd", -1.0, "command out of range: kd[1]")],
)
def test_a_bad_command_is_replaced_by_damping_and_is_a_fault(field, value, cause):
    """A controller command with a NaN or a negative gain never reaches the robot: damping, a fault."""
    s = machine()
    a = np.zeros(N)
    a[1] = value
    cmd = MotorCommand(**({k: np.zeros(N) for k in ("q", "dq", "kp", "kd", "tau")} | {field: a}))
    out = s.guard(cmd, frame(), 1.5)
    assert is_damping(out) and s.phase == "fault" and s.reason.startswith(cause) and s.since == 1.5


def test_every_command_is_clamped_to_range_speed_and_torque_at_the_measured_state():
    """q into the joint range, dq within the speed limit, and the torque the motor applies at the measured
    state, tau + kp (q - q_meas) + kd (dq - dq_meas), within the torque limit."""
    s = machine()
    meas = frame(q=(0.5, 0.0, 1.0), dq=(1.0, -1.0, 0.0))
    cmd = MotorCommand(
        q=np.array([3.0, -5.0, 1.0]),
        dq=np.array([100.0, 0.0, -100.0]),
        kp=np.array([100.0, 100.0, 0.0]),
        kd=np.array([1.0, 1.0, 0.0]),
        tau=np.array([0.0, 10.0, 500.0]),
    )
    out = s.guard(cmd, meas, 0.0)
    np.testing.assert_allclose(out.q, [1.0, -2.0, 1.0])
    np.testing.assert_allclose(out.dq, [20.0, 0.0, -30.0])
    applied = out.tau + out.kp * (out.q - meas.q) + out.kd * (out.dq - meas.dq)
    np.testing.assert_allclose(applied, [50.0, -80.0, 100.0])
    assert s.phase == "damping"  # clamping is no fault


def test_a_real_robot_is_taken_over_only_when_it_damps():
    """Every motor in mode 0, or every torque under 1 N m: accepted; an enabled motor holding torque: refused."""
    motors = [SimpleNamespace(mode=1, tau_est=0.2) for _ in range(N)]
    assert passive_at_start(SimpleNamespace(motor_state=motors), N)
    motors[1] = SimpleNamespace(mode=1, tau_est=12.0)
    assert not passive_at_start(SimpleNamespace(motor_state=motors), N)
    off = [SimpleNamespace(mode=0, tau_est=12.0) for _ in range(N)]
    assert passive_at_start(SimpleNamespace(motor_state=off), N)
