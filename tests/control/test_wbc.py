"""Whole-body inverse-dynamics QP on the G1: the solution obeys physics checked by other code.

Oracles: the QP's (qdd, f, tau) must satisfy the equations of motion as recomputed by MuJoCo's
recursive Newton-Euler (``mj_rne``), a different code path from the mass matrix the QP uses; its
contact forces must lie in the friction pyramids and under the per-foot normal-force caps; the contact
forces MuJoCo measures under a standing robot must carry its weight (Newton); ``rotation_error`` is
compared with SciPy's rotation vectors.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gaitshift.common.rotations import rot_z
from gaitshift.control.wbc import Gains, TickReference, WholeBodyController, rotation_error
from standing import standing


def _reference(com, feet, stance=(True, True), fz_max=1e4, com_acc=(0.0, 0.0, 0.0)):
    ref = TickReference.still(com, feet, stance, fz_max)
    ref.com_acc = np.asarray(com_acc, float)
    return ref


def _check_dynamics(plant, d, tau, info):
    """M qdd + bias = S^T tau + Jc^T f by mj_rne; unilateral, friction-cone forces; torque limits."""
    rne = np.zeros(plant.model.nv)
    d.qacc[:] = info.qdd
    mujoco.mj_rne(plant.model, d, 1, rne)  # M qdd + bias, by recursive Newton-Euler
    rne += plant.model.dof_armature * info.qdd  # rotor inertia: in M (mj_crb) but not in the RNE tree
    gen = info.contact_jacobian.T @ info.contact_forces
    gen[plant.actuated_dofs] += tau
    np.testing.assert_allclose(rne - d.qfrc_passive, gen, atol=1e-6 * np.max(np.abs(rne)))
    f = info.contact_forces.reshape(-1, 3)
    assert np.all(f[:, 2] >= -1e-9)
    assert np.all(np.abs(f[:, :2]) <= Gains().mu * f[:, 2:3] + 1e-6)
    assert np.all(np.abs(tau) <= plant.torque_limit + 1e-9)
    return f


def test_qp_solution_satisfies_the_equations_of_motion_by_newton_euler():
    plant, d, q0, feet = standing()
    ctrl = WholeBodyController(plant, q0)
    com = d.subtree_com[0] + [0.01, 0.02, -0.01]  # an offset reference so that the solution is not trivial
    tau, info = ctrl.compute(d, _reference(com, feet, com_acc=(0.3, -0.5, 0.2)))
    assert info.ok
    _check_dynamics(plant, d, tau, info)


def test_single_support_puts_all_force_on_the_stance_foot_under_its_cap():
    plant, d, q0, feet = standing()
    ctrl = WholeBodyController(plant, q0)
    cap = 0.8 * plant.mass * 9.81  # less than the weight: the CoM task cannot be met exactly
    lifted = feet + np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.02]])
    tau, info = ctrl.compute(d, _reference(d.subtree_com[0].copy(), lifted, stance=(True, False), fz_max=cap))
    assert info.ok
    f = _check_dynamics(plant, d, tau, info)
    assert len(f) == 4  # only the left sole's four points carry force
    assert f[:, 2].sum() <= cap + 1e-6
    assert f[:, 2].sum() > 0.5 * cap
    np.testing.assert_allclose(info.forces[0], f.sum(axis=0), atol=1e-9)
    assert np.all(info.forces[1] == 0.0)


def test_standing_robot_contact_forces_carry_its_weight():
    plant, d, q0, feet = standing()
    m = plant.model
    ctrl = WholeBodyController(plant, q0)
    ref = _reference(d.subtree_com[0].copy(), feet)
    cf = np.zeros(6)
    totals = []
    for k in range(500):  # 1 s
        mujoco.mj_forward(m, d)
        mujoco.mj_subtreeVel(m, d)
        tau, _ = ctrl.compute(d, ref)
        d.ctrl[:] = tau
        if k >= 250:
            fz = 0.0
            for i in range(d.ncon):
                mujoco.mj_contactForce(m, d, i, cf)
                fz += (d.contact[i].frame.reshape(3, 3).T @ cf[:3])[2]
            totals.append(fz)
        mujoco.mj_step(m, d)
    weight = plant.mass * 9.81
    assert np.mean(totals) == pytest.approx(weight, rel=0.01)
    assert abs(d.subtree_com[0, 2] - ref.com_pos[2]) < 0.005


def test_rotation_error_is_the_rotation_vector_taking_r_to_r_ref():
    rng = np.random.default_rng(1)
    for _ in range(20):
        R = Rotation.random(random_state=rng).as_matrix()
        R_ref = Rotation.random(random_state=rng).as_matrix()
        e = rotation_error(R_ref, R)
        np.testing.assert_allclose(e, Rotation.from_matrix(R_ref @ R.T).as_rotvec(), atol=1e-9)
    np.testing.assert_allclose(rotation_error(rot_z(0.3), rot_z(0.1)), [0.0, 0.0, 0.2], atol=1e-12)
