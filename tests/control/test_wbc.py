"""Whole-body inverse-dynamics QP on the G1: the solution obeys physics checked by other code.

Oracles: the QP's (qdd, w, tau) must satisfy the equations of motion as recomputed by MuJoCo's
recursive Newton-Euler (``mj_rne``), a different code path from the mass matrix the QP uses; each sole's
contact wrench must be exerted by forces at its contact points inside their friction pyramids (found
here by non-negative least squares on the pyramid edges) and stay under the per-foot normal-force cap;
the contact forces MuJoCo measures under a standing robot must carry its weight (Newton);
``rotation_error`` is compared with SciPy's rotation vectors.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from scipy.optimize import nnls
from scipy.spatial.transform import Rotation

from gaitshift.common.rotations import rot_z
from gaitshift.control.wbc import Gains, TickReference, WholeBodyController, rotation_error
from standing import standing


def _reference(com, feet, stance=(True, True), fz_max=1e4, com_acc=(0.0, 0.0, 0.0)):
    ref = TickReference.still(com, feet, stance, fz_max)
    ref.com_acc = np.asarray(com_acc, float)
    return ref


def _point_forces(plant, d, side, wrench):
    """Forces (n, 3) at the contact points of sole ``side`` in their pyramids (sole axes) exerting
    ``wrench`` (6,) [F; tau] about the sole centre, world frame (non-negative least squares on the
    pyramid edges); asserts that they exert it."""
    c, R = plant.sole_frame(d, side)
    mu = Gains().mu
    edges = R @ (np.array([[1, 1, 1], [1, -1, 1], [-1, 1, 1], [-1, -1, 1]], float) * [mu, mu, 1.0]).T  # (3, 4)
    arms = plant.contact_points(d, side) - c
    V = np.vstack([np.tile(edges, len(arms)), np.hstack([np.cross(r, edges.T).T for r in arms])])
    lam, residual = nnls(V, wrench)
    assert residual <= 1e-6 * np.linalg.norm(wrench)
    return (np.tile(edges, len(arms)) * lam).reshape(3, len(arms), 4).sum(axis=2).T


def _check_dynamics(plant, d, tau, info, stance=(0, 1)):
    """M qdd + bias = S^T tau + J^T w by mj_rne; each sole's wrench exerted by point forces in their
    pyramids; torque limits. Returns the point forces (n, 3) per stance sole."""
    rne = np.zeros(plant.model.nv)
    d.qacc[:] = info.qdd
    mujoco.mj_rne(plant.model, d, 1, rne)  # M qdd + bias, by recursive Newton-Euler
    rne += plant.model.dof_armature * info.qdd  # rotor inertia: in M (mj_crb) but not in the RNE tree
    gen = info.contact_jacobian.T @ info.contact_wrenches
    gen[plant.actuated_dofs] += tau
    np.testing.assert_allclose(rne - d.qfrc_passive, gen, atol=1e-6 * np.max(np.abs(rne)))
    assert np.all(np.abs(tau) <= plant.torque_limit + 1e-9)
    w = info.contact_wrenches.reshape(-1, 6)
    assert len(w) == len(stance)
    return [_point_forces(plant, d, s, w[j]) for j, s in enumerate(stance)]


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
    (f,) = _check_dynamics(plant, d, tau, info, stance=(0,))  # only the left sole carries force
    assert f[:, 2].sum() <= cap + 1e-6
    assert f[:, 2].sum() > 0.5 * cap
    np.testing.assert_allclose(info.forces[0], f.sum(axis=0), atol=1e-6)
    assert np.all(info.forces[1] == 0.0)


def test_the_reported_cop_is_the_centre_of_pressure_of_the_point_forces_that_exert_the_wrench():
    """TickInfo.cop_offset against the centre of pressure sum r_i f_iz / sum f_iz of point forces (in
    their pyramids, by NNLS) exerting the solved wrench, horizontal, from the sole centre; None for the
    swinging sole."""
    plant, d, q0, feet = standing()
    ctrl = WholeBodyController(plant, q0)
    lifted = feet + np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.02]])
    com = d.subtree_com[0] + [0.01, 0.015, 0.0]  # off the sole centre: a CoP away from it
    tau, info = ctrl.compute(d, _reference(com, lifted, stance=(True, False), com_acc=(0.4, -0.3, 0.0)))
    assert info.ok
    (f,) = _check_dynamics(plant, d, tau, info, stance=(0,))
    points = plant.contact_points(d, 0)
    cop = (points[:, :2] * f[:, 2:]).sum(axis=0) / f[:, 2].sum() - plant.sole_frame(d, 0)[0][:2]
    assert np.linalg.norm(cop) > 0.005
    np.testing.assert_allclose(info.cop_offset(0), cop, atol=1e-9)  # the points lie in the sole plane
    assert info.cop_offset(1) is None


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


def test_task_frame_jacobians_match_mujocos_at_a_moving_state():
    """The four task frames (one gather of the poses, the pelvis's angular rows in closed form on its
    free joint) against ``mj_jac``/``mj_jacDot`` and ``plant.sole_frame`` at a tilted, moving state."""
    plant, d, q0, _ = standing()
    m = plant.model
    rng = np.random.default_rng(2)
    d.qpos[3:7] = Rotation.from_rotvec([0.3, -0.2, 0.8]).as_quat(scalar_first=True)
    d.qpos[7:] += rng.uniform(-0.2, 0.2, m.nq - 7)
    d.qvel[:] = rng.normal(size=m.nv)
    mujoco.mj_forward(m, d)
    J, Jd, P, R = WholeBodyController(plant, q0).task_frames(d)
    bodies = [plant.soles[0].body, plant.soles[1].body, plant.torso_body, plant.pelvis_body]
    for i, body in enumerate(bodies):
        point = plant.sole_frame(d, i)[0] if i < 2 else d.xpos[body]
        jp, jr, dp, dr = (np.zeros((3, m.nv)) for _ in range(4))
        mujoco.mj_jac(m, d, jp, jr, point, body)
        mujoco.mj_jacDot(m, d, dp, dr, point, body)
        np.testing.assert_allclose(J[i, 3:], jr, atol=1e-12)
        np.testing.assert_allclose(Jd[i, 3:], dr @ d.qvel, atol=1e-9)
        if i < 2:  # the soles' linear rows and frames (the torso's and pelvis's positions are not tasks)
            np.testing.assert_allclose(J[i, :3], jp, atol=1e-12)
            np.testing.assert_allclose(Jd[i, :3], dp @ d.qvel, atol=1e-9)
            np.testing.assert_allclose(P[i], point, atol=1e-12)
            np.testing.assert_allclose(R[i], plant.sole_frame(d, i)[1], atol=1e-12)
