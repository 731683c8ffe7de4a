"""``rot_z``: a proper rotation about z, checked against its action on the x axis and composition.
``tilt_error``: a heading error alone is no tilt error however the body leans, and a rotation about a
level axis is its own angle (MuJoCo's quaternion algebra as the reference)."""

from __future__ import annotations

import mujoco
import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from gaitshift.common.rotations import rot_z, tilt_error

angles = st.floats(-10.0, 10.0, allow_nan=False)


@given(angles, angles)
def test_rot_z_is_a_rotation_about_z_and_composes_by_adding_angles(a, b):
    R = rot_z(a)
    assert R.shape == (3, 3)
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
    assert abs(np.linalg.det(R) - 1.0) < 1e-12
    np.testing.assert_allclose(R @ [1.0, 0.0, 0.0], [np.cos(a), np.sin(a), 0.0], atol=1e-12)
    np.testing.assert_allclose(R @ [0.0, 0.0, 1.0], [0.0, 0.0, 1.0], atol=0.0)
    np.testing.assert_allclose(rot_z(a) @ rot_z(b), rot_z(a + b), atol=1e-12)


def quat(axis: list[float], angle: float) -> np.ndarray:
    q = np.zeros(4)
    mujoco.mju_axisAngle2Quat(q, np.asarray(axis, float), angle)
    return q


def mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    q = np.zeros(4)
    mujoco.mju_mulQuat(q, a, b)
    return q


@given(angles, st.floats(-1.2, 1.2), st.floats(-1.2, 1.2), st.floats(-0.5, 0.5))
def test_a_heading_error_is_no_tilt_error_and_a_body_axis_rotation_is_its_angle(yaw, pitch, roll, err):
    body = mul(quat([0, 0, 1], yaw), mul(quat([0, 1, 0], pitch), quat([1, 0, 0], roll)))
    turned = mul(quat([0, 0, 1], err), body)  # the same lean, the heading off by err
    assert tilt_error(turned, body) < 1e-6
    tilted = mul(quat([np.cos(yaw), np.sin(yaw), 0.0], err), body)  # rotated about a level axis by err
    assert abs(tilt_error(tilted, body) - abs(err)) < 1e-6
