"""The G1's motors in the hg protocol's order: slot ``i`` of ``LowCmd_.motor_cmd`` and
``LowState_.motor_state`` is motor :data:`G1_MOTORS` ``[i]`` (Unitree's ``G1JointIndex``, 29 DoF).

The MuJoCo Menagerie ``unitree_g1/g1.xml`` lists its actuators in this same order, so a controller's
``motor_names`` for the G1 map onto slots 0-28 one to one (``tests/dds/test_g1_order.py``). Slots 29-34
are unused on the 29-DoF G1.
"""

from collections.abc import Sequence

from gaitshift.dds.messages import N_SLOTS
from gaitshift.errors import InputError

__all__ = ["G1_MOTORS", "check_motor_order"]

_LEG = ("hip_pitch", "hip_roll", "hip_yaw", "knee", "ankle_pitch", "ankle_roll")
_ARM = ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow", "wrist_roll", "wrist_pitch", "wrist_yaw")

#: hg slot -> the G1 joint (MJCF joint name): 0-5 left leg, 6-11 right leg, 12-14 waist, 15-21 left arm,
#: 22-28 right arm
G1_MOTORS: tuple[str, ...] = (
    *(f"left_{j}_joint" for j in _LEG),
    *(f"right_{j}_joint" for j in _LEG),
    "waist_yaw_joint",
    "waist_roll_joint",
    "waist_pitch_joint",
    *(f"left_{j}_joint" for j in _ARM),
    *(f"right_{j}_joint" for j in _ARM),
)


def check_motor_order(motor_names: Sequence[str]) -> int:
    """The number of motors when ``motor_names`` are the hg slots' joints in order (a prefix of
    :data:`G1_MOTORS`, at most :data:`N_SLOTS`); :class:`InputError` naming the first mismatch otherwise."""
    names = tuple(motor_names)
    if len(names) > N_SLOTS:
        raise InputError("motor_names", f"{len(names)} motors", f"at most {N_SLOTS} (the hg slots)")
    for i, name in enumerate(names):
        if i >= len(G1_MOTORS) or name != G1_MOTORS[i]:
            expected = G1_MOTORS[i] if i < len(G1_MOTORS) else "no motor"
            raise InputError(f"motor_names[{i}]", name, f"{expected} (the G1's hg motor order)")
    return len(names)
