"""SO(3)/SE_K(3) helpers against scipy and mink: the one-shot exp blocks (Exp^T, J_l^T, quaternion),
the rotation log, and the Rodrigues benchmark candidate, over tiny, small and large angles. The left
Jacobian is checked against its definition ``J_l(phi) = int_0^1 Exp(s phi) ds`` by quadrature (mink's
``SO3.ljac`` returns the identity below its epsilon, so it is compared on the large angle only)."""

from __future__ import annotations

import numpy as np
import pytest
from mink.lie import SO3
from scipy.integrate import simpson
from scipy.spatial.transform import Rotation

from gaitshift.control.estimation.lie import exp_blocks, exp_so3, log_rot, log_so3, quat_exp, rodrigues, skew

ANGLES = [np.array([1e-9, -2e-9, 3e-9]), np.array([3e-5, 1e-5, -2e-5]), np.array([0.3, -1.2, 0.7])]


@pytest.mark.parametrize("phi", ANGLES)
def test_exp_blocks_match_mink_and_scipy(phi):
    blocks, quat = exp_blocks(*phi)
    exp_t, jac_t = np.reshape(blocks[0:9], (3, 3)), np.reshape(blocks[9:18], (3, 3))
    np.testing.assert_allclose(exp_t, Rotation.from_rotvec(phi).as_matrix().T, atol=1e-12)
    s = np.linspace(0.0, 1.0, 201)
    jac = simpson(Rotation.from_rotvec(s[:, None] * phi).as_matrix(), x=s, axis=0)
    np.testing.assert_allclose(jac_t, jac.T, atol=1e-12)
    if np.linalg.norm(phi) > 0.1:
        np.testing.assert_allclose(jac_t, SO3.ljac(phi).T, atol=1e-12)
    np.testing.assert_allclose(Rotation.from_quat(quat, scalar_first=True).as_rotvec(), phi, atol=1e-12)
    np.testing.assert_allclose(quat_exp(*phi), quat, atol=1e-15)


@pytest.mark.parametrize("phi", ANGLES[1:])
def test_log_inverts_exp(phi):
    mat = Rotation.from_rotvec(phi).as_matrix()
    np.testing.assert_allclose(log_rot(mat.ravel().tolist()), phi, atol=1e-10)
    np.testing.assert_allclose(log_so3(mat), phi, atol=1e-10)
    np.testing.assert_allclose(rodrigues(phi), mat, atol=1e-12)
    np.testing.assert_allclose(exp_so3(phi), mat, atol=1e-12)


def test_skew_is_the_cross_product():
    a, b = np.array([0.3, -1.0, 2.0]), np.array([-0.5, 0.25, 1.5])
    np.testing.assert_allclose(skew(a) @ b, np.cross(a, b))
    np.testing.assert_allclose(skew(np.stack([a, b]))[1] @ a, np.cross(b, a))
