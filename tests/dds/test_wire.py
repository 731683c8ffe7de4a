"""gaitshift's hg messages are the official ones on the wire: for the same field values (random, seeded),
``serialize()`` gives byte for byte what Unitree's own IDL classes give (the SDK wheel ``unitree-sdk2==1.0.1``,
tests/unitree_oracle.py), each side reads the bytes back and writes them again unchanged, the type names are
Unitree's, and the serialized sizes are 1004 (``LowCmd_``) and 2092 (``LowState_``) bytes."""

import numpy as np
import pytest

import unitree_oracle
from gaitshift.dds import messages
from unitree_oracle import build_lowcmd, build_lowstate, lowcmd_fields, lowstate_fields

ORACLE = unitree_oracle.load()
pytestmark = pytest.mark.skipif(ORACLE is None, reason=unitree_oracle.SKIP_REASON)
N_MESSAGES = 40


@pytest.mark.parametrize("name", ["MotorCmd_", "LowCmd_", "IMUState_", "MotorState_", "LowState_"])
def test_type_names_are_unitrees(name):
    assert ORACLE is not None
    ours, theirs = getattr(messages, name), getattr(ORACLE.hg, name)
    assert ours.__idl_typename__ == theirs.__idl_typename__ == f"unitree_hg.msg.dds_.{name}"


def test_default_messages_serialize_alike_and_to_the_documented_sizes():
    assert ORACLE is not None
    zero_cmd = build_lowcmd(ORACLE.hg, lowcmd_fields(np.random.default_rng(0)) | {"mode_pr": 0})
    ours = messages.LowCmd_()
    theirs = type(zero_cmd).deserialize(ours.serialize())
    assert len(ours.serialize()) == 1004
    assert len(messages.LowState_().serialize()) == 2092
    assert theirs.serialize() == ours.serialize()


@pytest.mark.parametrize(
    ("build", "fields", "name"),
    [(build_lowcmd, lowcmd_fields, "LowCmd_"), (build_lowstate, lowstate_fields, "LowState_")],
)
def test_random_messages_serialize_byte_for_byte_like_the_sdk(build, fields, name):
    assert ORACLE is not None
    rng = np.random.default_rng(27)
    for _ in range(N_MESSAGES):
        values = fields(rng)
        ours, theirs = build(messages, values), build(ORACLE.hg, values)
        data = ours.serialize()
        assert data == theirs.serialize()
        # read back by the other side: the same values (uint8 arrays come back as bytes on both sides)
        back_ours, back_theirs = getattr(messages, name).deserialize(data), getattr(ORACLE.hg, name).deserialize(data)
        assert back_ours.serialize() == back_theirs.serialize() == data
        assert back_ours.crc == values["crc"] and back_ours.mode_machine == values["mode_machine"]
