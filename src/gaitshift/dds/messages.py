"""The Unitree "hg" low-level messages (G1, H1-2) as CycloneDDS IDL structs.

The same types, field order and type names as Unitree's own IDL (``unitree_hg/msg/dds_`` of
unitree_sdk2), so that a ``serialize()`` here gives the same bytes as the official SDK's classes
(``tests/dds/test_wire.py``) and a real robot or Unitree's simulator bridge accepts them. Each struct is
``@final`` with sequential member ids: XCDR with no member headers.

Units on the wire: angles rad, angular velocities rad/s, torques N m, gains N m/rad and N m s/rad,
accelerations m/s^2, temperatures degC, voltages V. Arrays have fixed lengths: a ``LowCmd_`` and a
``LowState_`` carry 35 motor slots (:data:`N_SLOTS`), of which the 29-DoF G1 uses the first 29.
"""

# no ``from __future__ import annotations`` here: cyclonedds reads the field annotations as objects
from dataclasses import dataclass, field

import cyclonedds.idl.annotations as annotate
from cyclonedds import idl
from cyclonedds.idl import types

__all__ = [
    "LOWCMD_TYPENAME",
    "LOWSTATE_TYPENAME",
    "N_SLOTS",
    "IMUState_",
    "LowCmd_",
    "LowState_",
    "MotorCmd_",
    "MotorState_",
]

#: motor slots in a LowCmd_ / LowState_
N_SLOTS = 35
LOWCMD_TYPENAME = "unitree_hg.msg.dds_.LowCmd_"
LOWSTATE_TYPENAME = "unitree_hg.msg.dds_.LowState_"


@dataclass
@annotate.final
@annotate.autoid("sequential")
class MotorCmd_(idl.IdlStruct, typename="unitree_hg.msg.dds_.MotorCmd_"):
    """One motor's command: ``mode`` 1 enabled, 0 disabled; targets ``q`` rad, ``dq`` rad/s; feed-forward
    ``tau`` N m; gains ``kp`` N m/rad, ``kd`` N m s/rad (the motor applies tau + kp (q - q_m) + kd (dq - dq_m))."""

    mode: types.uint8 = 0
    q: types.float32 = 0.0
    dq: types.float32 = 0.0
    tau: types.float32 = 0.0
    kp: types.float32 = 0.0
    kd: types.float32 = 0.0
    reserve: types.uint32 = 0


@dataclass
@annotate.final
@annotate.autoid("sequential")
class LowCmd_(idl.IdlStruct, typename=LOWCMD_TYPENAME):
    """The command on ``rt/lowcmd``: ``mode_pr`` (ankle 0 = pitch/roll, 1 = AB), ``mode_machine`` (copied
    from the robot's ``LowState_``), 35 motor slots, reserve, and the CRC of :mod:`gaitshift.dds.crc`."""

    mode_pr: types.uint8 = 0
    mode_machine: types.uint8 = 0
    motor_cmd: types.array[MotorCmd_, N_SLOTS] = field(default_factory=lambda: [MotorCmd_() for _ in range(N_SLOTS)])
    reserve: types.array[types.uint32, 4] = field(default_factory=lambda: [0, 0, 0, 0])
    crc: types.uint32 = 0


@dataclass
@annotate.final
@annotate.autoid("sequential")
class IMUState_(idl.IdlStruct, typename="unitree_hg.msg.dds_.IMUState_"):
    """The pelvis IMU: ``quaternion`` (4,) w x y z; ``gyroscope`` (3,) rad/s; ``accelerometer`` (3,) m/s^2
    specific force; ``rpy`` (3,) rad; ``temperature`` degC."""

    quaternion: types.array[types.float32, 4] = field(default_factory=lambda: [1.0, 0.0, 0.0, 0.0])
    gyroscope: types.array[types.float32, 3] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    accelerometer: types.array[types.float32, 3] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    rpy: types.array[types.float32, 3] = field(default_factory=lambda: [0.0, 0.0, 0.0])
    temperature: types.int16 = 0


@dataclass
@annotate.final
@annotate.autoid("sequential")
class MotorState_(idl.IdlStruct, typename="unitree_hg.msg.dds_.MotorState_"):
    """One motor's state: ``q`` rad, ``dq`` rad/s, ``ddq`` rad/s^2, ``tau_est`` N m, ``temperature`` (2,)
    degC, ``vol`` V, ``sensor`` (2,), ``motorstate`` (error bits), ``reserve`` (4,)."""

    mode: types.uint8 = 0
    q: types.float32 = 0.0
    dq: types.float32 = 0.0
    ddq: types.float32 = 0.0
    tau_est: types.float32 = 0.0
    temperature: types.array[types.int16, 2] = field(default_factory=lambda: [0, 0])
    vol: types.float32 = 0.0
    sensor: types.array[types.uint32, 2] = field(default_factory=lambda: [0, 0])
    motorstate: types.uint32 = 0
    reserve: types.array[types.uint32, 4] = field(default_factory=lambda: [0, 0, 0, 0])


@dataclass
@annotate.final
@annotate.autoid("sequential")
class LowState_(idl.IdlStruct, typename=LOWSTATE_TYPENAME):
    """The state on ``rt/lowstate``: ``version`` (2,), ``mode_pr``, ``mode_machine`` (the hardware variant),
    ``tick`` (the robot's counter, one per control period), the pelvis IMU, 35 motor slots,
    ``wireless_remote`` (40 bytes), reserve, and the CRC of :mod:`gaitshift.dds.crc`. No foot force."""

    version: types.array[types.uint32, 2] = field(default_factory=lambda: [0, 0])
    mode_pr: types.uint8 = 0
    mode_machine: types.uint8 = 0
    tick: types.uint32 = 0
    imu_state: IMUState_ = field(default_factory=IMUState_)
    motor_state: types.array[MotorState_, N_SLOTS] = field(
        default_factory=lambda: [MotorState_() for _ in range(N_SLOTS)]
    )
    wireless_remote: types.array[types.uint8, 40] = field(default_factory=lambda: [0] * 40)
    reserve: types.array[types.uint32, 4] = field(default_factory=lambda: [0, 0, 0, 0])
    crc: types.uint32 = 0
