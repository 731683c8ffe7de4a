"""The pieces of the reference IK (gaitshift.wholebody.ik_tasks), against closed forms:

* the sole orientation error leaves out exactly the free rotations: a pure roll about the sole's x
  axis is no error when roll is free, a pure pitch none when pitch is free, and with both free only the
  yaw is left;
* the soft range is mjlab's: centre +- fraction x half range, unlimited joints stay unlimited;
* the robot YAML's ``limits.soft_joint_fraction`` sets the range the reference IK keeps to (the default
  IK keeps the MJCF's, the model's own ranges are untouched), and a fraction outside (0, 1] is one
  ``InputError`` naming the key.
"""

from __future__ import annotations

import math
from importlib import resources

import numpy as np
import pytest

from gaitshift.common.rotations import rot_z
from gaitshift.errors import InputError
from gaitshift.robots import load_robot
from gaitshift.wholebody.ik import REFERENCE_SETTINGS, WholeBodyIK
from gaitshift.wholebody.ik_tasks import soft_range, sole_angle_error


def rot_x(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def rot_y(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


@pytest.mark.parametrize("yaw", [0.0, 1.2, -2.9])
def test_the_sole_error_leaves_out_exactly_the_free_rotations(yaw):
    target = rot_z(yaw)
    r, p, d = 0.3, -0.2, 0.05
    rolled, pitched, both = target @ rot_x(r), target @ rot_y(p), target @ rot_y(p) @ rot_x(r)
    assert sole_angle_error(target, rolled, False, False) == pytest.approx(r)
    assert sole_angle_error(target, rolled, True, False) == pytest.approx(0.0, abs=1e-7)
    assert sole_angle_error(target, rolled, False, True) == pytest.approx(r)  # roll still counts
    assert sole_angle_error(target, pitched, False, False) == pytest.approx(abs(p))
    assert sole_angle_error(target, pitched, False, True) == pytest.approx(0.0, abs=1e-7)
    assert sole_angle_error(target, pitched, True, False) == pytest.approx(abs(p))  # pitch still counts
    assert sole_angle_error(target, both, True, True) == pytest.approx(0.0, abs=1e-7)
    assert sole_angle_error(target, rot_z(d) @ both, True, True) == pytest.approx(d)  # only the yaw is left


def test_the_soft_range_is_the_centre_plus_minus_the_fraction_of_the_half_range():
    rng = np.array([[-1.0, 3.0], [-np.inf, np.inf], [0.0, 0.5]])
    soft = soft_range(rng, 0.9)
    np.testing.assert_allclose(soft[[0, 2]], [[1 - 1.8, 1 + 1.8], [0.025, 0.475]])
    assert np.all(np.isinf(soft[1]))
    np.testing.assert_array_equal(soft_range(rng, 1.0), rng)


def berkeley_with(tmp_path, name: str, tail: str) -> str:
    text = (resources.files("gaitshift.robots") / "configs" / "berkeley.yaml").read_text()
    path = tmp_path / f"{name}.yaml"
    path.write_text(text.replace("name: berkeley", f"name: {name}") + tail)
    return str(path)


def test_the_yaml_fraction_sets_the_range_the_reference_ik_keeps(tmp_path):
    robot = load_robot(berkeley_with(tmp_path, "b8", "\nlimits: {soft_joint_fraction: 0.8}\n"))
    assert robot.soft_joint_fraction == 0.8 and load_robot("berkeley").soft_joint_fraction == 0.9
    ref = WholeBodyIK(robot, REFERENCE_SETTINGS)
    np.testing.assert_allclose(ref.joint_range, soft_range(robot.joint_range, 0.8))
    lim = ref.limits[0].model
    ids = [lim.joint(n).id for n in robot.joint_names]
    np.testing.assert_allclose(lim.jnt_range[ids], soft_range(robot.joint_range, 0.8))
    np.testing.assert_allclose(ref.model.jnt_range[ids], robot.joint_range)  # the IK's own model untouched
    np.testing.assert_array_equal(WholeBodyIK(robot).joint_range, robot.joint_range)


@pytest.mark.parametrize("value", ["0", "1.5", "-0.2", "'x'"])
def test_a_fraction_outside_zero_to_one_is_one_input_error_naming_the_key(tmp_path, value):
    path = berkeley_with(tmp_path, f"bad{abs(hash(value))}", f"\nlimits: {{soft_joint_fraction: {value}}}\n")
    with pytest.raises(InputError, match=r"robot\.limits\.soft_joint_fraction") as exc:
        load_robot(path)
    assert len(str(exc.value).splitlines()) == 1
