"""``rot_z``: a proper rotation about z, checked against its action on the x axis and composition."""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from gaitshift.common.rotations import rot_z

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
