"""The G1's hg motor order (slot i of LowCmd_/LowState_) is the MuJoCo Menagerie G1's actuator order and
the controller's ``motor_names``: the model's own names, slot by slot; a different order is an InputError."""

import mujoco
import pytest

from gaitshift.dds.g1 import G1_MOTORS, check_motor_order
from gaitshift.errors import InputError
from gaitshift.robots.config import load_robot
from gaitshift.robots.model import robot_model


def test_menagerie_g1_actuators_are_the_hg_motor_order():
    raw = mujoco.MjModel.from_xml_path(str(load_robot("g1").mjcf))
    names = [raw.actuator(i).name for i in range(raw.nu)]
    joints = [raw.joint(raw.actuator_trnid[i, 0]).name for i in range(raw.nu)]
    assert len(G1_MOTORS) == 29
    assert names == joints == list(G1_MOTORS)
    assert names[:6] == [
        f"left_{j}_joint" for j in ("hip_pitch", "hip_roll", "hip_yaw", "knee", "ankle_pitch", "ankle_roll")
    ]
    assert names[12:15] == ["waist_yaw_joint", "waist_roll_joint", "waist_pitch_joint"]
    assert names[15] == "left_shoulder_pitch_joint" and names[22] == "right_shoulder_pitch_joint"


def test_the_controllers_motor_names_map_one_to_one_on_slots_0_to_28():
    assert check_motor_order(robot_model("g1").motor_names) == 29


def test_a_different_order_is_an_input_error():
    swapped = list(G1_MOTORS)
    swapped[3], swapped[4] = swapped[4], swapped[3]
    with pytest.raises(InputError, match=r"motor_names\[3\]"):
        check_motor_order(swapped)
    with pytest.raises(InputError, match="motor_names"):
        check_motor_order(list(G1_MOTORS) + ["x"] * 7)
