"""The robot model's shared helpers (src/gaitshift/robots/model.py)."""

from __future__ import annotations

import copy

import mujoco
import numpy as np
import pytest

from gaitshift.robots.model import forward_terms, robot_model, standing_qpos

#: what the controller reads of its MjData: frames, CoM, the mass matrix, the bias and passive forces
READ = ("xpos", "xmat", "xquat", "site_xpos", "site_xmat", "subtree_com", "cdof", "cvel", "cdof_dot")
FORCES = ("qfrc_bias", "qfrc_passive")


@pytest.mark.parametrize("contacts", [True, False])
def test_the_forward_terms_are_mj_forwards_own_on_all_the_controller_reads(contacts):
    """At a random state (the G1 in the air and moving), :func:`forward_terms` leaves in ``MjData`` the same
    frames, mass matrix and bias and passive forces as MuJoCo's whole ``mj_forward``, to the last bit, and
    the accelerations it leaves out stay unset."""
    robot = robot_model("g1")
    model = copy.copy(robot.model)
    if not contacts:
        model.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
    rng = np.random.default_rng(3)
    qpos = standing_qpos(robot) + np.r_[0.0, 0.0, 0.3, np.zeros(4), rng.normal(0.0, 0.2, model.nq - 7)]
    qvel = rng.normal(0.0, 1.0, model.nv)
    full, part = mujoco.MjData(model), mujoco.MjData(model)
    for d in (full, part):
        d.qpos[:], d.qvel[:] = qpos, qvel
    mujoco.mj_forward(model, full)
    forward_terms(model, part)
    for name in READ + FORCES:
        np.testing.assert_array_equal(getattr(part, name), getattr(full, name), err_msg=name)
    mass = np.zeros((2, model.nv, model.nv))
    for m, d in zip(mass, (full, part), strict=True):
        mujoco.mj_fullM(model, d, m)
    np.testing.assert_array_equal(mass[1], mass[0])
    assert np.abs(full.qfrc_bias).max() > 1.0  # gravity and the velocities: the identity is not of zeros
    assert not part.qacc.any()  # the accelerations are not computed
