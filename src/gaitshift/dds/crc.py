"""The CRC of Unitree's hg low-level messages, as the official SDK computes it (``unitree_sdk2py``
``utils/crc.py``, ``CRC().Crc(msg)``), in a few microseconds.

The message is packed little-endian with C alignment (:data:`PACK_FORMATS`, the SDK's formats: a
``LowCmd_`` is 1004 bytes, a ``LowState_`` 2092), read as 32-bit words ``w_0 .. w_{n-1}``, and the CRC
runs over all words but the last (the ``crc`` field itself):

    CRC-32, polynomial 0x04C11DB7, initial register 0xFFFFFFFF, each word fed MSB first,
    no reflection, no final xor                                                            (1)

that is CRC-32/MPEG-2 over the words' big-endian bytes. The SDK's pure-Python routine takes ~2.6 ms
per ``LowCmd_``. Here (1) runs in zlib's C CRC-32 through the bit-reflection identity

    mpeg2(M) = reflect32(zlib.crc32(reflect_bytes(M), 0) xor 0xFFFFFFFF)                  (2)

(zlib's CRC-32 is the reflected form of the same polynomial, with ``~start`` as initial register and a
final ``~``: with start 0 the register starts at 0xFFFFFFFF, which is its own reflection). ``M`` here is
the words' big-endian bytes: the packed bytes with each word's byte order swapped, and
``reflect_bytes`` reverses the bits of every byte (a 256-entry ``bytes.translate`` table).
"""

import struct
import zlib
from collections.abc import Callable
from typing import Any

from gaitshift.dds.messages import LOWCMD_TYPENAME, LOWSTATE_TYPENAME, N_SLOTS
from gaitshift.errors import InputError

__all__ = [
    "CRCS",
    "PACK_FORMATS",
    "crc32_mpeg2",
    "crc_of",
    "lowcmd_crc",
    "lowstate_crc",
    "pack_lowcmd",
    "pack_lowstate",
    "words_crc",
]

#: the SDK's struct formats (4-byte aligned, little-endian), by IDL type name
PACK_FORMATS: dict[str, str] = {
    LOWCMD_TYPENAME: "<2B2x" + "B3x5fI" * N_SLOTS + "5I",
    LOWSTATE_TYPENAME: "<2I2B2xI" + "13fh2x" + "B3x4f2hf7I" * N_SLOTS + "40B5I",
}
_LOWCMD = struct.Struct(PACK_FORMATS[LOWCMD_TYPENAME])
_LOWSTATE = struct.Struct(PACK_FORMATS[LOWSTATE_TYPENAME])
#: byte -> the byte with its 8 bits in reverse order
_REFLECT = bytes(int(f"{b:08b}"[::-1], 2) for b in range(256))


def _reflect32(x: int) -> int:
    """The 32 bits of ``x`` in reverse order."""
    return int.from_bytes(x.to_bytes(4, "little").translate(_REFLECT), "big")


def crc32_mpeg2(data: bytes) -> int:
    """CRC-32/MPEG-2 of ``data`` (poly 0x04C11DB7, init 0xFFFFFFFF, MSB first, no xor out): eq. (2)."""
    return _reflect32(zlib.crc32(data.translate(_REFLECT), 0) ^ 0xFFFFFFFF)


def words_crc(packed: bytes) -> int:
    """Eq. (1) over the little-endian 32-bit words of ``packed`` (length a multiple of 4), all of them."""
    if len(packed) % 4:
        raise InputError("packed message", f"{len(packed)} bytes", "a multiple of 4 bytes")
    swapped = bytearray(packed)
    for i in range(4):  # each word's bytes in big-endian order
        swapped[i::4] = packed[3 - i :: 4]
    return crc32_mpeg2(bytes(swapped))


def pack_lowcmd(msg: Any) -> bytes:
    """The SDK's packing of a hg ``LowCmd_`` (1004 bytes): mode_pr, mode_machine, 35 x (mode, q, dq, tau,
    kp, kd, reserve), reserve[4], crc. Any object with these fields (the SDK's class too)."""
    values: list[Any] = [msg.mode_pr, msg.mode_machine]
    for m in msg.motor_cmd:
        values += (m.mode, m.q, m.dq, m.tau, m.kp, m.kd, m.reserve)
    values += (*msg.reserve, msg.crc)
    return _pack(_LOWCMD, values, LOWCMD_TYPENAME)


def pack_lowstate(msg: Any) -> bytes:
    """The SDK's packing of a hg ``LowState_`` (2092 bytes): version[2], mode_pr, mode_machine, tick, the
    IMU (quaternion, gyroscope, accelerometer, rpy, temperature), 35 x (mode, q, dq, ddq, tau_est,
    temperature[2], vol, sensor[2], motorstate, reserve[4]), wireless_remote[40], reserve[4], crc."""
    imu = msg.imu_state
    values: list[Any] = [*msg.version, msg.mode_pr, msg.mode_machine, msg.tick]
    values += (*imu.quaternion, *imu.gyroscope, *imu.accelerometer, *imu.rpy, imu.temperature)
    for m in msg.motor_state:
        values += (m.mode, m.q, m.dq, m.ddq, m.tau_est, *m.temperature, m.vol, *m.sensor, m.motorstate, *m.reserve)
    values += (*msg.wireless_remote, *msg.reserve, msg.crc)
    return _pack(_LOWSTATE, values, LOWSTATE_TYPENAME)


def _pack(layout: struct.Struct, values: list[Any], typename: str) -> bytes:
    try:
        return layout.pack(*values)
    except struct.error as e:  # a wrong length, an integer out of its range, not a number
        raise InputError(typename, str(e), f"the fields of a {typename}, each in its IDL type's range") from None


def lowcmd_crc(msg: Any) -> int:
    """The CRC of a hg ``LowCmd_`` (its ``crc`` field ignored): the value to put into ``msg.crc``."""
    return words_crc(pack_lowcmd(msg)[:-4])


def lowstate_crc(msg: Any) -> int:
    """The CRC of a hg ``LowState_`` (its ``crc`` field ignored): the value to put into ``msg.crc``."""
    return words_crc(pack_lowstate(msg)[:-4])


#: IDL type name -> its CRC (the SDK's ``Crc`` dispatches the same way)
CRCS: dict[str, Callable[[Any], int]] = {LOWCMD_TYPENAME: lowcmd_crc, LOWSTATE_TYPENAME: lowstate_crc}


def crc_of(msg: Any) -> int:
    """The CRC of a hg ``LowCmd_`` or ``LowState_``, by its IDL type name; :class:`InputError` otherwise."""
    name = getattr(msg, "__idl_typename__", type(msg).__name__)
    if name not in CRCS:
        raise InputError("message type", name, " or ".join(CRCS))
    return CRCS[name](msg)
