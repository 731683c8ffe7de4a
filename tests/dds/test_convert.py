"""The conversions between gaitshift's frames and the hg messages are exact to float32 through the wire
(SensorFrame -> LowState_ -> bytes -> LowState_ -> SensorFrame, MotorCommand -> LowCmd_ -> bytes -> LowCmd_
-> MotorCommand), put ``mode = 1`` on every used slot, copy ``mode_machine`` and ``tick``, set a CRC that
a corrupted message fails, and turn every bad value (NaN, a wrong length, a negative gain, an integer
out of range, a mode outside 0/1) into one InputError naming the field."""

import numpy as np
import pytest

from gaitshift.control.frames import MotorCommand, SensorFrame
from gaitshift.dds.convert import command_from_lowcmd, frame_from_lowstate, lowcmd_from_command, lowstate_from_frame
from gaitshift.dds.crc import lowcmd_crc, lowstate_crc
from gaitshift.dds.messages import LowCmd_, LowState_
from gaitshift.errors import InputError

N = 29


def f32(a):
    return np.asarray(a, dtype=float).astype(np.float32).astype(float)


def random_command(rng):
    return MotorCommand(
        q=rng.normal(size=N),
        dq=rng.normal(size=N) * 5,
        kp=rng.uniform(0, 200, N),
        kd=rng.uniform(0, 5, N),
        tau=rng.normal(size=N) * 30,
    )


def random_frame(rng):
    quat = rng.normal(size=4)
    return SensorFrame(
        t=0.25,
        imu_quat=quat / np.linalg.norm(quat),
        imu_gyro=rng.normal(size=3),
        imu_acc=rng.normal(size=3) * 9.81,
        q=rng.normal(size=N),
        dq=rng.normal(size=N),
        tau_est=rng.normal(size=N) * 20,
    )


def test_command_round_trip_through_the_wire_is_exact_to_float32():
    rng = np.random.default_rng(1)
    for _ in range(20):
        cmd = random_command(rng)
        sent = lowcmd_from_command(cmd, mode_machine=5)
        received = LowCmd_.deserialize(sent.serialize())
        assert received == sent and received.crc == lowcmd_crc(received)
        assert [m.mode for m in received.motor_cmd] == [1] * N + [0] * 6
        assert received.mode_machine == 5 and received.mode_pr == 0
        back = command_from_lowcmd(received, N)
        for name in ("q", "dq", "kp", "kd", "tau"):
            np.testing.assert_array_equal(getattr(back, name), f32(getattr(cmd, name)), err_msg=name)


def test_state_round_trip_through_the_wire_is_exact_to_float32():
    rng = np.random.default_rng(2)
    for k in range(20):
        frame = random_frame(rng)
        sent = lowstate_from_frame(frame, tick=1000 + k, mode_machine=7)
        received = LowState_.deserialize(sent.serialize())
        assert received.tick == 1000 + k and received.mode_machine == 7
        assert [m.mode for m in received.motor_state] == [1] * N + [0] * 6
        back = frame_from_lowstate(received, t=frame.t, n_motors=N)
        assert back.t == frame.t and back.foot_force is None
        for name in ("imu_quat", "imu_gyro", "imu_acc", "q", "dq", "tau_est"):
            np.testing.assert_array_equal(getattr(back, name), f32(getattr(frame, name)), err_msg=name)


def test_the_state_carries_roll_pitch_yaw_of_the_quaternion():
    half = 0.3 / 2  # 0.3 rad about z
    frame = random_frame(np.random.default_rng(3))
    frame = SensorFrame(**{**frame.__dict__, "imu_quat": np.array([np.cos(half), 0, 0, np.sin(half)])})
    np.testing.assert_allclose(lowstate_from_frame(frame, 0, 0).imu_state.rpy, [0, 0, 0.3], atol=1e-6)


def test_a_corrupted_message_fails_its_crc():
    cmd = lowcmd_from_command(random_command(np.random.default_rng(4)), mode_machine=5)
    data = bytearray(cmd.serialize())
    data[100] ^= 0x01  # one bit of a motor's field
    with pytest.raises(InputError, match=r"LowCmd_\.crc"):
        command_from_lowcmd(LowCmd_.deserialize(bytes(data)), N)
    state = lowstate_from_frame(random_frame(np.random.default_rng(5)), 9, 5)
    state.crc ^= 1
    with pytest.raises(InputError, match=r"LowState_\.crc"):
        frame_from_lowstate(state, 0.0, N)


def test_a_disabled_slot_is_zero_torque():
    msg = lowcmd_from_command(random_command(np.random.default_rng(6)), mode_machine=5)
    msg.motor_cmd[3].mode = 0
    msg.crc = lowcmd_crc(msg)
    cmd = command_from_lowcmd(msg, N)
    assert cmd.kp[3] == cmd.kd[3] == cmd.tau[3] == 0.0 and cmd.kp[4] > 0


@pytest.mark.parametrize(
    ("change", "field"),
    [
        ({"q": np.r_[np.zeros(N - 1), np.nan]}, r"MotorCommand\.q\[28\]"),
        ({"tau": np.zeros(N - 1)}, r"MotorCommand\.tau"),
        ({"kp": np.r_[-1.0, np.zeros(N - 1)]}, r"MotorCommand\[0\]\.kp"),
        ({"dq": np.full(N, 1e39)}, r"MotorCommand\.dq\[0\]"),
    ],
)
def test_a_bad_command_is_one_input_error_naming_the_field(change, field):
    cmd = MotorCommand(**{**random_command(np.random.default_rng(7)).__dict__, **change})
    with pytest.raises(InputError, match=field):
        lowcmd_from_command(cmd, mode_machine=5)


def test_bad_integers_and_bad_messages_are_input_errors_naming_the_field():
    rng = np.random.default_rng(8)
    with pytest.raises(InputError, match=r"LowCmd_\.mode_machine"):
        lowcmd_from_command(random_command(rng), mode_machine=256)
    msg = lowcmd_from_command(random_command(rng), mode_machine=5)
    msg.motor_cmd[2].mode = 2
    msg.crc = lowcmd_crc(msg)
    with pytest.raises(InputError, match=r"LowCmd_\.motor_cmd\[2\]\.mode"):
        command_from_lowcmd(msg, N)
    msg.motor_cmd = msg.motor_cmd[:30]
    with pytest.raises(InputError, match=r"LowCmd_\.motor_cmd"):
        command_from_lowcmd(msg, N)
    state = lowstate_from_frame(random_frame(rng), 0, 5)
    state.motor_state[4].dq = float("nan")
    state.imu_state.quaternion = [2.0, 0.0, 0.0, 0.0]
    state.crc = lowstate_crc(state)
    with pytest.raises(InputError, match=r"LowState_\.motor_state\.dq\[4\]"):
        frame_from_lowstate(state, 0.0, N)
    state.motor_state[4].dq = 0.0
    state.crc = lowstate_crc(state)
    with pytest.raises(InputError, match=r"LowState_\.imu_state\.quaternion"):
        frame_from_lowstate(state, 0.0, N)
