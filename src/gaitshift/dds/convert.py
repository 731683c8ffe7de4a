"""Between gaitshift's frames (:class:`~gaitshift.control.frames.SensorFrame`,
:class:`~gaitshift.control.frames.MotorCommand`) and the hg messages (:mod:`gaitshift.dds.messages`).

Motor ``i`` of a frame (the controller's ``motor_names`` order, :func:`gaitshift.dds.g1.check_motor_order`)
is slot ``i`` of the message; slots past the robot's motors are left disabled and zero. The host side
(the controller's computer)::

    frame = frame_from_lowstate(state, t, n)           the CRC checked; IMU, q, dq, tau_est of slots 0..n-1
    msg = lowcmd_from_command(cmd, state.mode_machine)  mode 1 on every motor, the CRC set

and the robot side (a simulated robot behind the protocol, :mod:`gaitshift.dds.robot`) the reverse,
:func:`lowstate_from_frame` and :func:`command_from_lowcmd`. The brain's fast path reads and writes the
messages' bytes (:mod:`gaitshift.dds.cdr`): ``frame_from_lowstate`` also takes a
:class:`~gaitshift.dds.cdr.StateBytes`, and :func:`lowcmd_bytes` is the serialized ``lowcmd_from_command``,
with the same checks and the same errors. Values travel as float32: a round trip is
exact to float32. A bad message (a wrong CRC, a wrong length, NaN or infinity, a negative gain, a mode
outside 0/1, an integer outside its type) is one :class:`~gaitshift.errors.InputError` naming its field.
"""

from collections.abc import Sequence
from typing import Any

import numpy as np

from gaitshift.common.rotations import roll_pitch_yaw
from gaitshift.control.frames import MotorCommand, SensorFrame
from gaitshift.dds.cdr import HEADER, LOWCMD, StateBytes
from gaitshift.dds.crc import lowcmd_crc, lowstate_crc
from gaitshift.dds.messages import N_SLOTS, IMUState_, LowCmd_, LowState_, MotorCmd_, MotorState_
from gaitshift.errors import InputError

__all__ = [
    "command_from_lowcmd",
    "frame_from_lowstate",
    "lowcmd_bytes",
    "lowcmd_from_command",
    "lowstate_from_frame",
]

F32_MAX = float(np.finfo(np.float32).max)
COMMAND_FIELDS = ("q", "dq", "tau", "kp", "kd")
#: SensorFrame field -> the LowState_ field it comes from (for error messages)
STATE_FIELDS = {
    "imu_quat": "imu_state.quaternion",
    "imu_gyro": "imu_state.gyroscope",
    "imu_acc": "imu_state.accelerometer",
    "q": "motor_state.q",
    "dq": "motor_state.dq",
    "tau_est": "motor_state.tau_est",
}


def _floats(field: str, value: Any, size: int) -> np.ndarray:
    """``value`` as float64 (size,), finite and within float32; :class:`InputError` naming the first bad entry."""
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(field, value, f"{size} numbers") from None
    if a.shape != (size,):
        raise InputError(field, f"shape {a.shape}", f"{size} numbers")
    bad = ~(np.abs(a) <= F32_MAX)  # NaN compares False
    if bad.any():
        i = int(np.argmax(bad))
        raise InputError(f"{field}[{i}]", float(a[i]), "a finite float32")
    return a


def _as_sent(a: np.ndarray) -> list[Any]:
    """``a`` rounded to float32, as Python floats: the message in memory equals the one received."""
    out: list[Any] = a.astype(np.float32).astype(float).tolist()
    return out


def _uint(field: str, value: Any, bits: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or not 0 <= value < 1 << bits:
        raise InputError(field, value, f"an integer in [0, {(1 << bits) - 1}]")
    return int(value)


def _gains_nonnegative(kind: str, kp: np.ndarray, kd: np.ndarray) -> None:
    for name, g in (("kp", kp), ("kd", kd)):
        if (g < 0).any():
            i = int(np.argmax(g < 0))
            raise InputError(f"{kind}[{i}].{name}", float(g[i]), "a gain >= 0")


def _command_rows(cmd: MotorCommand) -> np.ndarray:
    """(n, 5) q, dq, tau, kp, kd of ``cmd`` (n <= 35 motors), checked: finite, within float32, gains >= 0."""
    n = int(np.size(cmd.q))
    if n > N_SLOTS:
        raise InputError("MotorCommand.q", f"{n} motors", f"at most {N_SLOTS}")
    a = {k: _floats(f"MotorCommand.{k}", getattr(cmd, k), n) for k in COMMAND_FIELDS}
    _gains_nonnegative("MotorCommand", a["kp"], a["kd"])
    return np.stack([a[k] for k in COMMAND_FIELDS], axis=1)


def lowcmd_from_command(cmd: MotorCommand, mode_machine: int, mode_pr: int = 0) -> LowCmd_:
    """The ``LowCmd_`` of ``cmd`` (n motors, n <= 35): slots 0..n-1 enabled (``mode = 1``) with q rad,
    dq rad/s, tau N m, kp N m/rad, kd N m s/rad; ``mode_machine`` copied from the robot's state; the CRC set."""
    rows = _as_sent(_command_rows(cmd))
    n = len(rows)
    motors = [MotorCmd_(mode=1, q=q, dq=dq, tau=tau, kp=kp, kd=kd) for q, dq, tau, kp, kd in rows]
    motors += [MotorCmd_() for _ in range(N_SLOTS - n)]
    fields: dict[str, Any] = {
        "mode_pr": _uint("LowCmd_.mode_pr", mode_pr, 1),
        "mode_machine": _uint("LowCmd_.mode_machine", mode_machine, 8),
        "motor_cmd": motors,
    }
    msg = LowCmd_(**fields)
    msg.crc = lowcmd_crc(msg)
    return msg


def lowcmd_bytes(cmd: MotorCommand, mode_machine: int, mode_pr: int = 0) -> bytes:
    """``lowcmd_from_command(cmd, mode_machine, mode_pr).serialize()``, written directly (the same bytes,
    :mod:`gaitshift.dds.cdr`; the same checks)."""
    rows = _command_rows(cmd)
    n = len(rows)
    body = np.zeros(LOWCMD.size, np.uint8)
    LOWCMD.write(body, "mode_pr", _uint("LowCmd_.mode_pr", mode_pr, 1))
    LOWCMD.write(body, "mode_machine", _uint("LowCmd_.mode_machine", mode_machine, 8))
    LOWCMD.write(body, "motor_cmd.mode", np.ones(n))
    for j, k in enumerate(COMMAND_FIELDS):
        LOWCMD.write(body, f"motor_cmd.{k}", rows[:, j])
    LOWCMD.write(body, "crc", LOWCMD.crc(body))
    return HEADER + body.tobytes()


def _check_crc(msg: Any, kind: str, expected: int) -> None:
    if msg.crc != expected:
        raise InputError(f"{kind}.crc", msg.crc, f"the CRC of the message, {expected}")


def _slots(msg: Any, kind: str, name: str) -> Sequence[Any]:
    slots: Sequence[Any] | None = getattr(msg, name, None)
    if slots is None or len(slots) != N_SLOTS:
        raise InputError(f"{kind}.{name}", "missing" if slots is None else f"{len(slots)} slots", f"{N_SLOTS} slots")
    return slots


def command_from_lowcmd(msg: LowCmd_, n_motors: int) -> MotorCommand:
    """The :class:`MotorCommand` of slots 0..n_motors-1 of ``msg`` after its CRC is checked; a disabled slot
    (``mode = 0``) becomes zero torque (kp = kd = tau = 0)."""
    kind = "LowCmd_"
    slots = _slots(msg, kind, "motor_cmd")
    _check_crc(msg, kind, lowcmd_crc(msg))
    used = slots[:n_motors]
    modes = np.array([m.mode for m in used])
    if not np.isin(modes, (0, 1)).all():
        i = int(np.argmax(~np.isin(modes, (0, 1))))
        raise InputError(f"{kind}.motor_cmd[{i}].mode", int(modes[i]), "0 (disabled) or 1 (enabled)")
    rows = np.array([(m.q, m.dq, m.tau, m.kp, m.kd) for m in used], dtype=float).reshape(-1, 5)
    a = {k: _floats(f"{kind}.motor_cmd.{k}", rows[:, j], len(used)) for j, k in enumerate(COMMAND_FIELDS)}
    _gains_nonnegative(f"{kind}.motor_cmd", a["kp"], a["kd"])
    on = modes == 1
    return MotorCommand(q=a["q"], dq=a["dq"], kp=a["kp"] * on, kd=a["kd"] * on, tau=a["tau"] * on)


def lowstate_from_frame(frame: SensorFrame, tick: int, mode_machine: int, mode_pr: int = 0) -> LowState_:
    """The ``LowState_`` a robot sends for ``frame`` (n motors in slots 0..n-1, ``mode = 1``; the IMU with
    its roll, pitch, yaw): ``tick`` the robot's counter (taken modulo 2^32), the CRC set. The frame's
    ``foot_force`` and ``oracle`` are not carried (the hg state has no such fields)."""
    n = int(np.size(frame.q))
    if n > N_SLOTS:
        raise InputError("SensorFrame.q", f"{n} motors", f"at most {N_SLOTS}")
    per_motor = {k: _floats(f"SensorFrame.{k}", getattr(frame, k), n) for k in ("q", "dq", "tau_est")}
    quat = _floats("SensorFrame.imu_quat", frame.imu_quat, 4)
    imu_fields: dict[str, Any] = {
        "quaternion": _as_sent(quat),
        "gyroscope": _as_sent(_floats("SensorFrame.imu_gyro", frame.imu_gyro, 3)),
        "accelerometer": _as_sent(_floats("SensorFrame.imu_acc", frame.imu_acc, 3)),
        "rpy": _as_sent(roll_pitch_yaw(quat)),
    }
    rows = _as_sent(np.stack([per_motor["q"], per_motor["dq"], per_motor["tau_est"]], axis=1))
    motors = [MotorState_(mode=1, q=q, dq=dq, tau_est=tau) for q, dq, tau in rows]
    motors += [MotorState_() for _ in range(N_SLOTS - n)]
    tick = _uint("LowState_.tick", int(tick) % (1 << 32) if isinstance(tick, int | np.integer) else tick, 32)
    fields: dict[str, Any] = {
        "mode_pr": _uint("LowState_.mode_pr", mode_pr, 1),
        "mode_machine": _uint("LowState_.mode_machine", mode_machine, 8),
        "tick": tick,
        "imu_state": IMUState_(**imu_fields),
        "motor_state": motors,
    }
    msg = LowState_(**fields)
    msg.crc = lowstate_crc(msg)
    return msg


def _state_values(msg: LowState_ | StateBytes, n_motors: int) -> tuple[dict[str, Any], bool]:
    """The frame's fields of slots 0..n_motors-1 of ``msg`` (a message or its bytes), its CRC checked; and
    whether they are known good already (float64 arrays of float32 values, all finite)."""
    kind = "LowState_"
    if isinstance(msg, StateBytes):
        _check_crc(msg, kind, msg.expected_crc())
        n = min(max(n_motors, 0), N_SLOTS)
        (quat, gyro, acc, q, dq, tau), finite = msg.frame_floats()
        fast = {"imu_quat": quat, "imu_gyro": gyro, "imu_acc": acc, "q": q[:n], "dq": dq[:n], "tau_est": tau[:n]}
        return fast, finite
    slots = _slots(msg, kind, "motor_state")
    _check_crc(msg, kind, lowstate_crc(msg))
    rows = np.array([(m.q, m.dq, m.tau_est) for m in slots[:n_motors]], dtype=float).reshape(-1, 3)
    imu = msg.imu_state
    values: dict[str, Any] = {
        "imu_quat": imu.quaternion,
        "imu_gyro": imu.gyroscope,
        "imu_acc": imu.accelerometer,
        "q": rows[:, 0],
        "dq": rows[:, 1],
        "tau_est": rows[:, 2],
    }
    return values, False


def frame_from_lowstate(msg: LowState_ | StateBytes, t: float, n_motors: int) -> SensorFrame:
    """The :class:`SensorFrame` at time ``t`` s of slots 0..n_motors-1 of ``msg`` (a message, or its bytes as
    received) after its CRC is checked: the IMU (quaternion w x y z, gyro rad/s, accelerometer m/s^2), q rad,
    dq rad/s, tau_est N m; no foot force (the hg state has none)."""
    kind = "LowState_"
    fields, good = _state_values(msg, n_motors)
    n = len(fields["q"])
    if not good:  # each field checked, the first bad entry named (finite float32 values pass as they are)
        sizes = {"imu_quat": 4, "imu_gyro": 3, "imu_acc": 3}
        fields = {k: _floats(f"{kind}.{STATE_FIELDS[k]}", v, sizes.get(k, n)) for k, v in fields.items()}
    try:
        return SensorFrame.checked(n, t=t, **fields)
    except InputError as e:  # the unit quaternion, the time: named as the message's field
        field = STATE_FIELDS.get(e.field.removeprefix("SensorFrame."), e.field.removeprefix("SensorFrame."))
        raise InputError(f"{kind}.{field}" if field != "t" else "t", e.value, e.allowed) from None
