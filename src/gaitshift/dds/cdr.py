"""The hg messages' bytes on the wire (CDR), read and written with numpy: the brain's fast path.

cyclonedds's Python ``serialize()`` / ``deserialize()`` of a ``LowCmd_`` / ``LowState_`` build and walk
hundreds of Python objects: 0.30 ms and 0.45 ms per message on this machine. The two messages are
``@final`` structs of fixed size made of primitives only, so their CDR bytes are a fixed layout:

    4-byte encapsulation header (00 01 00 00: plain CDR, little-endian), then every primitive in IDL
    order, each aligned to its own size (1, 2 or 4 bytes) from the end of the header             (1)

(a 1004-byte ``LowCmd_``, a 2092-byte ``LowState_``). The layout (1) is built here from the same
primitives as the SDK's packing of :mod:`gaitshift.dds.crc` (:data:`~gaitshift.dds.crc.PACK_FORMATS`,
where a struct starts at its alignment instead: the two layouts differ by a few padding bytes), so
that a message's CRC is the packing's CRC of the same bytes, gathered (:meth:`Layout.packed`).
``tests/dds/test_cdr.py`` proves the bytes equal cyclonedds's and the official SDK's for random messages.

The other encapsulations (big-endian, XCDR2's 00 07: the same layout for these types) are refused: a
:class:`~gaitshift.errors.InputError`.
"""

import re
import struct
from dataclasses import dataclass

import numpy as np

from gaitshift.dds.crc import PACK_FORMATS, words_crc
from gaitshift.dds.messages import LOWCMD_TYPENAME, LOWSTATE_TYPENAME, N_SLOTS
from gaitshift.errors import InputError

__all__ = ["FRAME_FIELDS", "HEADER", "LOWCMD", "LOWSTATE", "Layout", "StateBytes"]

#: the encapsulation header cyclonedds writes for these types: plain CDR, little-endian, no options
HEADER = b"\x00\x01\x00\x00"

#: per message, its primitives in IDL order: (field path, count); a motor slot's fields repeat N_SLOTS times
_MOTOR_CMD = [("mode", 1), ("q", 1), ("dq", 1), ("tau", 1), ("kp", 1), ("kd", 1), ("reserve", 1)]
_MOTOR_STATE = [
    ("mode", 1),
    ("q", 1),
    ("dq", 1),
    ("ddq", 1),
    ("tau_est", 1),
    ("temperature", 2),
    ("vol", 1),
    ("sensor", 2),
    ("motorstate", 1),
    ("reserve", 4),
]
_IMU = [("quaternion", 4), ("gyroscope", 3), ("accelerometer", 3), ("rpy", 3), ("temperature", 1)]
_FIELDS = {
    LOWCMD_TYPENAME: [("mode_pr", 1), ("mode_machine", 1)]
    + [(f"motor_cmd.{n}", c) for _ in range(N_SLOTS) for n, c in _MOTOR_CMD]
    + [("reserve", 4), ("crc", 1)],
    LOWSTATE_TYPENAME: [("version", 2), ("mode_pr", 1), ("mode_machine", 1), ("tick", 1)]
    + [(f"imu_state.{n}", c) for n, c in _IMU]
    + [(f"motor_state.{n}", c) for _ in range(N_SLOTS) for n, c in _MOTOR_STATE]
    + [("wireless_remote", 40), ("reserve", 4), ("crc", 1)],
}
_DTYPES = {"B": "u1", "h": "<i2", "I": "<u4", "f": "<f4"}


@dataclass(frozen=True)
class Layout:
    """One message's CDR layout (1) and the gather to the SDK's packing.

    Attributes:
        typename: the IDL type name. size: bytes after the header.
        fields: path -> (byte indices (k, itemsize) into the body, numpy dtype), k the values in IDL order
            (e.g. ``motor_state.q``: the 35 slots).
        gather: (packed size,) the body index of each byte of the SDK's packing; ``size`` for a padding byte
            (the zero appended by :meth:`packed`).
    """

    typename: str
    size: int
    fields: dict[str, tuple[np.ndarray, np.dtype]]
    gather: np.ndarray

    @classmethod
    def of(cls, typename: str) -> "Layout":
        """The layout of ``typename`` (a LowCmd_ or LowState_ type name), from :data:`_FIELDS` and the
        SDK's format of :data:`~gaitshift.dds.crc.PACK_FORMATS` (their primitives must agree)."""
        codes = [c * int(n or 1) for n, c in re.findall(r"(\d*)([BhIfx])", PACK_FORMATS[typename])]
        flat = "".join(codes)
        prims = [c for c in flat if c != "x"]
        paths = [p for p, count in _FIELDS[typename] for _ in range(count)]
        if len(paths) != len(prims):
            raise AssertionError(f"{typename}: {len(paths)} fields, {len(prims)} primitives in its pack format")
        cdr, packed, pos, at = [], [], 0, 0
        for c in flat:
            size = struct.calcsize(c)
            if c == "x":
                at += 1
                continue
            pos += -pos % size  # (1): aligned to its size
            cdr.append(pos)
            packed.append(at)
            pos, at = pos + size, at + size
        body = pos + -pos % 4
        gather = np.full(at, body, dtype=np.intp)
        offsets: dict[str, list[int]] = {}
        for path, c, o, p in zip(paths, prims, cdr, packed, strict=True):
            n = struct.calcsize(c)
            gather[p : p + n] = np.arange(o, o + n)
            offsets.setdefault(path, []).append(o)
        fields = {}
        for path, offs in offsets.items():
            dt = np.dtype(_DTYPES[prims[paths.index(path)]])
            fields[path] = (np.asarray(offs)[:, None] + np.arange(dt.itemsize), dt)
        return cls(typename, body, fields, gather)

    def read(self, body: np.ndarray, path: str) -> np.ndarray:
        """The values of ``path`` in the body bytes (uint8), in IDL order."""
        idx, dt = self.fields[path]
        out: np.ndarray = body[idx].view(dt).ravel()
        return out

    def write(self, body: np.ndarray, path: str, values: object, first: int = 0) -> None:
        """Write ``values`` (converted to the field's type) into the body bytes, from the ``first``-th value."""
        idx, dt = self.fields[path]
        v = np.ascontiguousarray(np.atleast_1d(np.asarray(values, dtype=dt)))
        body[idx[first : first + len(v)]] = v.view(np.uint8).reshape(len(v), dt.itemsize)

    def packed(self, body: np.ndarray) -> bytes:
        """The SDK's packing of the message (its CRC's input, :mod:`gaitshift.dds.crc`)."""
        out: bytes = np.append(body, np.uint8(0))[self.gather].tobytes()
        return out

    def crc(self, body: np.ndarray) -> int:
        """The message's CRC (its ``crc`` field ignored): :func:`~gaitshift.dds.crc.words_crc` of the packing."""
        return words_crc(self.packed(body)[:-4])

    def body_of(self, data: bytes) -> np.ndarray:
        """The body bytes (uint8, read-only) of a serialized message; :class:`InputError` for another
        encapsulation or a short message."""
        if data[:4] != HEADER:
            raise InputError(f"{self.typename} encapsulation", data[:4].hex(), f"{HEADER.hex()} (CDR, little-endian)")
        if len(data) < 4 + self.size:
            raise InputError(f"{self.typename} length", len(data), f"at least {4 + self.size} bytes")
        return np.frombuffer(data, np.uint8, count=self.size, offset=4)


LOWCMD = Layout.of(LOWCMD_TYPENAME)
LOWSTATE = Layout.of(LOWSTATE_TYPENAME)
#: the float32 fields a SensorFrame is made of, in this order (4, 3, 3, 35, 35, 35 values), and their bytes
FRAME_FIELDS = (
    "imu_state.quaternion",
    "imu_state.gyroscope",
    "imu_state.accelerometer",
    "motor_state.q",
    "motor_state.dq",
    "motor_state.tau_est",
)
_FRAME_INDEX = np.concatenate([LOWSTATE.fields[f][0] for f in FRAME_FIELDS])
_FRAME_SPLIT = np.cumsum([len(LOWSTATE.fields[f][0]) for f in FRAME_FIELDS])[:-1]


class StateBytes:
    """A ``LowState_`` as received: its CDR bytes, with the fields the brain reads.

    Attributes:
        data: the serialized message. body: its bytes after the header (uint8).
        tick, mode_machine, crc: the message's fields (ints).
    """

    def __init__(self, data: bytes) -> None:
        self.data = data
        self.body = LOWSTATE.body_of(data)
        self.tick = int(LOWSTATE.read(self.body, "tick")[0])
        self.mode_machine = int(LOWSTATE.read(self.body, "mode_machine")[0])
        self.crc = int(LOWSTATE.read(self.body, "crc")[0])
        self._expected: int | None = None

    def expected_crc(self) -> int:
        """The CRC of the message (the value its ``crc`` field must hold), computed once."""
        if self._expected is None:
            self._expected = LOWSTATE.crc(self.body)
        return self._expected

    def frame_floats(self) -> tuple[list[np.ndarray], bool]:
        """The :data:`FRAME_FIELDS` as float64 arrays (one gather), and whether every value is finite."""
        flat = self.body[_FRAME_INDEX].view("<f4").ravel().astype(float)
        return np.split(flat, _FRAME_SPLIT), bool(np.isfinite(flat).all())

    def field(self, path: str) -> np.ndarray:
        """The values of ``path`` (e.g. ``motor_state.q``: (35,) float32 rad)."""
        return LOWSTATE.read(self.body, path)
