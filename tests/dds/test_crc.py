"""gaitshift's CRC of the hg messages equals the official SDK's (``CRC().Crc(msg)`` of the wheel
``unitree-sdk2==1.0.1``: its packing and its pure-Python CRC-32) on 300 random ``LowCmd_`` and 100 random
``LowState_`` (seeded), for gaitshift's classes and the SDK's alike; the CRC-32/MPEG-2 kernel gives the
catalogue check value; a message of another type or a packing that cannot be done is an InputError."""

import numpy as np
import pytest

import unitree_oracle
from gaitshift.dds import messages
from gaitshift.dds.crc import crc32_mpeg2, crc_of, lowcmd_crc, lowstate_crc, pack_lowcmd, words_crc
from gaitshift.errors import InputError
from unitree_oracle import build_lowcmd, build_lowstate, lowcmd_fields, lowstate_fields

ORACLE = unitree_oracle.load()
needs_oracle = pytest.mark.skipif(ORACLE is None, reason=unitree_oracle.SKIP_REASON)


def test_the_kernel_is_crc32_mpeg2():
    assert crc32_mpeg2(b"123456789") == 0x0376E6E7  # the catalogue's check value of CRC-32/MPEG-2
    assert crc32_mpeg2(b"") == 0xFFFFFFFF
    # one word 0x00000001 fed MSB first is the bytes 00 00 00 01
    assert words_crc((1).to_bytes(4, "little")) == crc32_mpeg2(b"\x00\x00\x00\x01")


@needs_oracle
def test_lowcmd_crc_equals_the_sdks_on_300_random_messages():
    assert ORACLE is not None
    rng = np.random.default_rng(2027)
    for _ in range(300):
        values = lowcmd_fields(rng)
        theirs = build_lowcmd(ORACLE.hg, values)
        expected = ORACLE.crc(theirs)
        assert lowcmd_crc(build_lowcmd(messages, values)) == expected
        assert crc_of(theirs) == expected  # their class through our packing


@needs_oracle
def test_lowstate_crc_equals_the_sdks_on_100_random_messages():
    assert ORACLE is not None
    rng = np.random.default_rng(2028)
    for _ in range(100):
        values = lowstate_fields(rng)
        theirs = build_lowstate(ORACLE.hg, values)
        assert lowstate_crc(build_lowstate(messages, values)) == ORACLE.crc(theirs) == crc_of(theirs)


def test_the_crc_field_itself_is_not_covered():
    msg = messages.LowCmd_(mode_machine=3)
    before = lowcmd_crc(msg)
    msg.crc = 12345
    assert lowcmd_crc(msg) == before
    msg.motor_cmd[7].kp = 1.5
    assert lowcmd_crc(msg) != before


def test_another_type_or_an_unpackable_message_is_an_input_error():
    with pytest.raises(InputError, match="message type"):
        crc_of(messages.MotorCmd_())
    bad = messages.LowCmd_(mode_machine=300)
    with pytest.raises(InputError, match="LowCmd_"):
        pack_lowcmd(bad)
    with pytest.raises(InputError, match="multiple of 4"):
        words_crc(b"abc")
