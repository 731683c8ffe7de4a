"""Leg kinematics against MuJoCo forward kinematics of the G1 done here, independently: a fresh MjData
with a known floating-base pose and joint angles, ``mj_forward``, then the soles, CoM and base seen
from the IMU site; velocities and encoder-noise variances against finite differences of that FK.
Both the pelvis IMU (on the base) and the torso IMU (behind the waist joints) are checked."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from gaitshift.control.estimation import LegKinematics
from gaitshift.control.estimation.kinematics import kinematic_model
from gaitshift.robots import load_robot

H = 1e-6  # finite-difference step, rad


@pytest.fixture(scope="module")
def g1():
    return load_robot("g1")


def _pose(model, rng):
    qpos = model.qpos0.copy()
    qpos[0:3] = [0.3, -0.2, 0.8]
    quat = rng.normal(size=4)
    qpos[3:7] = quat / np.linalg.norm(quat)
    lo, hi = model.jnt_range[1:, 0], model.jnt_range[1:, 1]
    qpos[7:] = lo + (hi - lo) * rng.uniform(0.3, 0.7, model.nv - 6)
    return qpos


def _seen_from(model, qpos, imu):
    """Soles, CoM, base origin (4, 3), sole rotations (2, 3, 3), base rotation, in the IMU frame."""
    d = mujoco.MjData(model)
    d.qpos[:] = qpos
    mujoco.mj_forward(model, d)
    r_imu, p_imu = d.site(imu).xmat.reshape(3, 3), d.site(imu).xpos
    pts = np.array([d.site(s).xpos for s in load_robot("g1").SOLE_SITES] + [d.subtree_com[1], d.xpos[1]])
    rots = np.array([d.site(s).xmat.reshape(3, 3) for s in load_robot("g1").SOLE_SITES])
    return (pts - p_imu) @ r_imu, r_imu.T @ rots, r_imu.T @ d.xmat[1].reshape(3, 3)


@pytest.mark.parametrize("imu", ["imu_in_pelvis", "imu_in_torso"])
def test_positions_and_orientations_match_mujoco_forward_kinematics(g1, imu):
    model = g1.model()
    kin = LegKinematics.from_robot(g1, imu_site=imu)
    rng = np.random.default_rng(4)
    for _ in range(3):
        qpos = _pose(model, rng)
        pts, rots, base_rot = _seen_from(model, qpos, imu)
        out = kin.compute(qpos[7:], np.zeros(model.nv - 6))
        np.testing.assert_allclose(out.points, pts, atol=1e-10)
        np.testing.assert_allclose(out.feet.pos, pts[0:2], atol=1e-10)
        np.testing.assert_allclose(out.feet.rot, rots, atol=1e-10)
        np.testing.assert_allclose(out.base_rot, base_rot, atol=1e-10)


@pytest.mark.parametrize("imu", ["imu_in_pelvis", "imu_in_torso"])
def test_velocities_match_finite_differences_of_the_fk(g1, imu):
    model = g1.model()
    kin = LegKinematics.from_robot(g1, imu_site=imu)
    rng = np.random.default_rng(5)
    qpos = _pose(model, rng)
    qd = rng.normal(0.0, 1.0, model.nv - 6)
    ahead, behind = qpos.copy(), qpos.copy()
    ahead[7:] += H * qd
    behind[7:] -= H * qd
    (p1, _, r1), (p0, _, r0) = _seen_from(model, ahead, imu), _seen_from(model, behind, imu)
    out = kin.compute(qpos[7:], qd)
    np.testing.assert_allclose(out.points_vel, (p1 - p0) / (2 * H), atol=1e-6)
    np.testing.assert_allclose(out.feet.vel, (p1[0:2] - p0[0:2]) / (2 * H), atol=1e-6)
    spin = (r1 - r0) / (2 * H) @ out.base_rot.T  # d(base_rot)/dt base_rot^T = [omega]x
    np.testing.assert_allclose(out.base_omega, [spin[2, 1], spin[0, 2], spin[1, 0]], atol=1e-6)


def test_encoder_variance_is_the_trace_of_j_sigma_jt_over_three(g1):
    model = g1.model()
    sigma = 0.01
    kin = LegKinematics.from_robot(g1, encoder_std=sigma)
    qpos = _pose(model, np.random.default_rng(6))
    base, _, _ = _seen_from(model, qpos, "imu_in_pelvis")
    jac = np.zeros((2, 3, model.nv - 6))
    for j in range(model.nv - 6):  # finite-difference Jacobian of the soles, column by column
        moved = qpos.copy()
        moved[7 + j] += H
        jac[:, :, j] = (_seen_from(model, moved, "imu_in_pelvis")[0][0:2] - base[0:2]) / H
    out = kin.compute(qpos[7:], np.zeros(model.nv - 6))
    expected = sigma**2 * np.einsum("fij,fij->f", jac, jac) / 3.0
    np.testing.assert_allclose(out.feet.var, expected, rtol=1e-4)


def test_kinematics_never_touch_another_mjdata(g1):
    model = g1.model()
    sim = mujoco.MjData(model)
    sim.qpos[:] = _pose(model, np.random.default_rng(7))
    before = sim.qpos.copy()
    kin = LegKinematics.from_robot(g1)
    kin.compute(np.zeros(model.nv - 6), np.ones(model.nv - 6))
    assert kin.data is not sim
    np.testing.assert_array_equal(sim.qpos, before)
    np.testing.assert_array_equal(kin.data.qpos[3:7], [1.0, 0.0, 0.0, 0.0])  # free joint at identity


@pytest.mark.parametrize("imu", ["imu_in_pelvis", "imu_in_torso"])
def test_the_model_without_geoms_gives_the_same_numbers(g1, imu):
    """The estimator's private model drops the geoms; every kinematic output stays bit-identical."""
    bare = kinematic_model(g1)
    assert bare.ngeom == 0 and g1.model().ngeom > 0
    full_kin = LegKinematics(g1.model(), imu, g1.SOLE_SITES, encoder_std=0.01)
    bare_kin = LegKinematics(bare, imu, g1.SOLE_SITES, encoder_std=0.01)
    rng = np.random.default_rng(8)
    for _ in range(9):  # past a variance refresh (every VAR_EVERY ticks)
        qpos, qd = _pose(g1.model(), rng), rng.normal(0.0, 1.0, bare.nv - 6)
        a, b = full_kin.compute(qpos[7:], qd), bare_kin.compute(qpos[7:], qd)
        for name in ("points", "points_vel", "base_rot", "base_omega"):
            np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
        for name in ("pos", "vel", "var", "rot", "rot_var"):
            np.testing.assert_array_equal(getattr(a.feet, name), getattr(b.feet, name))
