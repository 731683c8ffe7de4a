"""The brain's fast path on the wire (gaitshift.dds.cdr) writes and reads the official bytes: for random
field values (seeded), a command written by ``lowcmd_bytes`` is byte for byte ``lowcmd_from_command(...)
.serialize()``, which the SDK's class (tests/unitree_oracle.py) reads and writes again unchanged and whose
CRC the SDK's routine computes alike; a state serialized by the SDK's class is read by ``StateBytes``
field for field, its CRC is the SDK's, and ``frame_from_lowstate`` gives the same frame from the bytes as
from the deserialized message. Bad input is the same one-line InputError on both paths (a NaN, a negative
gain, a wrong CRC), and another encapsulation or a short message is refused."""

import numpy as np
import pytest

import unitree_oracle
from gaitshift.control.frames import MotorCommand
from gaitshift.dds import messages
from gaitshift.dds.cdr import HEADER, LOWCMD, LOWSTATE, StateBytes
from gaitshift.dds.convert import frame_from_lowstate, lowcmd_bytes, lowcmd_from_command
from gaitshift.dds.crc import lowstate_crc
from gaitshift.errors import InputError
from unitree_oracle import build_lowstate, lowstate_fields

ORACLE = unitree_oracle.load()
N = 29
N_MESSAGES = 40


def random_command(rng, n=N):
    """Values over many magnitudes (as the oracle's random fields), gains >= 0."""
    scale = 10.0 ** rng.integers(-6, 7, size=(5, n))
    q, dq, tau, kp, kd = rng.normal(size=(5, n)) * scale
    return MotorCommand(q=q, dq=dq, tau=tau, kp=np.abs(kp), kd=np.abs(kd))


def test_the_layouts_have_the_messages_sizes():
    assert len(HEADER) + LOWCMD.size == len(messages.LowCmd_().serialize()) == 1004
    assert len(HEADER) + LOWSTATE.size == len(messages.LowState_().serialize()) == 2092
    assert LOWSTATE.fields["motor_state.q"][0].shape == (35, 4)


@pytest.mark.skipif(ORACLE is None, reason=unitree_oracle.SKIP_REASON)
def test_a_command_written_directly_is_the_official_message():
    assert ORACLE is not None
    rng = np.random.default_rng(5)
    for k in range(N_MESSAGES):
        cmd, mm = random_command(rng, n=[N, 35, 12, 0][k % 4]), int(rng.integers(0, 256))
        data = lowcmd_bytes(cmd, mm, k % 2)
        assert data == lowcmd_from_command(cmd, mm, k % 2).serialize()
        theirs = ORACLE.hg.LowCmd_.deserialize(data)
        assert theirs.serialize() == data
        assert ORACLE.crc(theirs) == theirs.crc and theirs.mode_machine == mm
        assert [m.mode for m in theirs.motor_cmd] == [1] * len(cmd.q) + [0] * (35 - len(cmd.q))


@pytest.mark.skipif(ORACLE is None, reason=unitree_oracle.SKIP_REASON)
def test_a_state_read_from_its_bytes_is_the_official_message():
    assert ORACLE is not None
    rng = np.random.default_rng(6)
    for _ in range(N_MESSAGES):
        values = lowstate_fields(rng)
        theirs = build_lowstate(ORACLE.hg, values)
        data = theirs.serialize()
        s = StateBytes(data)
        assert (s.tick, s.mode_machine, s.crc) == (values["tick"], values["mode_machine"], values["crc"])
        assert s.expected_crc() == ORACLE.crc(theirs)
        for key in ("version", "mode_pr", "wireless_remote", "reserve"):
            assert s.field(key).tolist() == np.atleast_1d(values[key]).tolist(), key
        for key, v in values["imu_state"].items():
            assert s.field(f"imu_state.{key}").tolist() == np.atleast_1d(v).tolist(), key
        for key in values["motor_state"][0]:
            column = np.array([m[key] for m in values["motor_state"]]).ravel()
            assert s.field(f"motor_state.{key}").tolist() == column.tolist(), key


def good_state(rng):
    """A state with a unit quaternion and a good CRC, serialized."""
    values = lowstate_fields(rng)
    quat = rng.normal(size=4)
    values["imu_state"]["quaternion"] = [float(x) for x in (quat / np.linalg.norm(quat)).astype(np.float32)]
    msg = build_lowstate(messages, values)
    msg.crc = lowstate_crc(msg)
    return msg


def test_the_frame_from_the_bytes_is_the_frame_from_the_message():
    rng = np.random.default_rng(7)
    for _ in range(10):
        msg = good_state(rng)
        a = frame_from_lowstate(StateBytes(msg.serialize()), 0.5, N)
        b = frame_from_lowstate(messages.LowState_.deserialize(msg.serialize()), 0.5, N)
        for key in ("t", "imu_quat", "imu_gyro", "imu_acc", "q", "dq", "tau_est"):
            assert np.array_equal(getattr(a, key), getattr(b, key)), key


def error_of(f, *args):
    with pytest.raises(InputError) as e:
        f(*args)
    return str(e.value)


def test_bad_input_is_the_same_error_on_both_paths():
    rng = np.random.default_rng(8)
    cmd = random_command(rng)
    cmd.q[4] = np.nan
    assert error_of(lowcmd_bytes, cmd, 0) == error_of(lowcmd_from_command, cmd, 0)
    cmd = random_command(rng)
    cmd.kd[2] = -1.0
    assert error_of(lowcmd_bytes, cmd, 0) == error_of(lowcmd_from_command, cmd, 0)
    assert error_of(lowcmd_bytes, random_command(rng), 256).startswith("LowCmd_.mode_machine = 256")
    msg = good_state(rng)
    msg.motor_state[3].q = float("nan")
    msg.crc = lowstate_crc(msg)
    data = msg.serialize()
    message = error_of(frame_from_lowstate, StateBytes(data), 0.0, N)
    assert message == error_of(frame_from_lowstate, messages.LowState_.deserialize(data), 0.0, N)
    assert message.startswith("LowState_.motor_state.q[3] = nan")
    msg.crc ^= 1
    data = msg.serialize()
    message = error_of(frame_from_lowstate, StateBytes(data), 0.0, N)
    assert message == error_of(frame_from_lowstate, messages.LowState_.deserialize(data), 0.0, N)
    assert message.startswith("LowState_.crc = ")


def test_another_encapsulation_or_a_short_message_is_refused():
    data = messages.LowState_().serialize()
    assert error_of(StateBytes, b"\x00\x00" + data[2:]).startswith("unitree_hg.msg.dds_.LowState_ encapsulation")
    assert error_of(StateBytes, data[:-8]).startswith("unitree_hg.msg.dds_.LowState_ length = 2084")
