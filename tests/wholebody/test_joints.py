"""Joint trajectories: manifold differences against MuJoCo's own, velocities against closed forms,
the joints file, and plan subsampling.

Oracles: ``mj_differentiatePos`` (MuJoCo's configuration difference) for :func:`qpos_difference`; a
free body spinning at a known constant body rate and hinges moving as sines (derivatives known in
closed form) for :func:`joint_velocities`; the file is read back with plain ``np.load``/``json``.
"""

from __future__ import annotations

import json

import mujoco
import numpy as np
import pytest

import gaitshift
from gaitshift.errors import InputError
from gaitshift.robots import load_robot
from gaitshift.wholebody.joints import (
    JointTrajectory,
    coordinate_names,
    joint_velocities,
    load_plan,
    qpos_difference,
    subsample,
)


@pytest.fixture(scope="module")
def g1_model():
    return load_robot("g1").model()


def _random_qpos(model, rng, n):
    q = np.tile(model.qpos0, (n, 1))
    q[:, :3] = rng.normal(size=(n, 3))
    quat = rng.normal(size=(n, 4))
    q[:, 3:7] = quat / np.linalg.norm(quat, axis=1, keepdims=True)
    q[:, 7:] = rng.uniform(-1.0, 1.0, size=(n, model.nq - 7))
    return q


def test_qpos_difference_matches_mujoco_differentiate_pos(g1_model):
    rng = np.random.default_rng(3)
    q0, q1 = _random_qpos(g1_model, rng, 20), _random_qpos(g1_model, rng, 20)
    q1[:10, 3:7] = q0[:10, 3:7] * np.cos(0.3) + rng.normal(size=(10, 4)) * 0.05  # also small rotations
    q1[:10, 3:7] /= np.linalg.norm(q1[:10, 3:7], axis=1, keepdims=True)
    batch = qpos_difference(g1_model, q0, q1)
    for k in range(20):
        ref = np.empty(g1_model.nv)
        mujoco.mj_differentiatePos(g1_model, ref, 1.0, q0[k], q1[k])
        np.testing.assert_allclose(batch[k], ref, atol=1e-12)


def test_joint_velocities_of_a_spinning_body_and_sine_joints_are_second_order_accurate(g1_model):
    """Free body: constant body rate w (quat(t) = exp(t w / 2)), linear velocity v; hinges q_j = sin(a_j t).
    The central-difference error must drop 4x when dt halves (second order)."""
    w, v = np.array([0.4, -0.2, 0.9]), np.array([0.3, 0.1, -0.2])
    a = np.linspace(0.5, 3.0, g1_model.nq - 7)

    def error(dt):
        t = np.arange(0.0, 1.0 + dt / 2, dt)
        theta = np.linalg.norm(w) * t
        axis = w / np.linalg.norm(w)
        q = np.zeros((len(t), g1_model.nq))
        q[:, :3] = t[:, None] * v
        q[:, 3] = np.cos(theta / 2)
        q[:, 4:7] = np.sin(theta / 2)[:, None] * axis
        q[:, 7:] = np.sin(t[:, None] * a)
        exact = np.hstack([np.tile(v, (len(t), 1)), np.tile(w, (len(t), 1)), np.cos(t[:, None] * a) * a])
        qvel = joint_velocities(g1_model, q, dt)
        return np.max(np.abs(qvel[1:-1] - exact[1:-1]))

    e1, e2 = error(0.01), error(0.005)
    assert e1 < 1e-3
    assert 3.5 < e1 / e2 < 4.5


def test_joints_file_round_trips_and_holds_strict_json_meta(g1_model, tmp_path):
    rng = np.random.default_rng(0)
    q = _random_qpos(g1_model, rng, 5)
    meta = {"robot": "g1", "ik": {"max_com_error_m": float("nan")}}
    jt = JointTrajectory(np.arange(5) * 0.01, q, np.zeros((5, g1_model.nv)), meta)
    path = jt.save(tmp_path / "j.npz")
    with np.load(path) as z:
        assert set(z.files) == {"t", "qpos", "qvel", "meta"}
        np.testing.assert_array_equal(z["qpos"], q)
        stored = json.loads(str(z["meta"]), parse_constant=lambda c: pytest.fail(f"{c} in meta"))
    assert stored["ik"]["max_com_error_m"] is None
    back = JointTrajectory.load(path)
    np.testing.assert_array_equal(back.t, jt.t)
    np.testing.assert_array_equal(back.qvel, jt.qvel)


def test_joints_file_rejects_other_suffixes_and_files_without_the_keys(tmp_path):
    jt = JointTrajectory(np.zeros(1), np.zeros((1, 8)), np.zeros((1, 7)))
    with pytest.raises(InputError, match="npz"):
        jt.save(tmp_path / "j.csv")
    assert not (tmp_path / "j.csv").exists()
    np.savez(tmp_path / "other.npz", t=np.zeros(2))
    with pytest.raises(InputError, match="missing"):
        JointTrajectory.load(tmp_path / "other.npz")
    with pytest.raises(InputError, match="existing"):
        JointTrajectory.load(tmp_path / "absent.npz")


def test_coordinate_names_follow_the_mujoco_qpos_and_qvel_layout(g1_model):
    qpos_names, qvel_names = coordinate_names(g1_model)
    assert len(qpos_names) == g1_model.nq and len(qvel_names) == g1_model.nv
    assert qpos_names[3:7] == [f"{qpos_names[0].split(':')[0]}:{c}" for c in ("qw", "qx", "qy", "qz")]
    for j in range(1, g1_model.njnt):
        assert qpos_names[g1_model.jnt_qposadr[j]] == g1_model.joint(j).name
        assert qvel_names[g1_model.jnt_dofadr[j]] == g1_model.joint(j).name


def test_subsample_keeps_every_kth_sample_and_rejects_rates_off_the_grid():
    traj = gaitshift.plan("g1-walk")
    sub = subsample(traj, 0.25 / traj.dt)  # every 4th sample
    assert len(sub) == len(traj.t[::4])
    np.testing.assert_array_equal(sub.t, traj.t[::4])
    np.testing.assert_array_equal(sub.com_pos, traj.com_pos[::4])
    np.testing.assert_array_equal(sub.footsteps, traj.footsteps)
    assert subsample(traj, None) is traj and subsample(traj, 1.0 / traj.dt) is traj
    for bad in (0.3 / traj.dt, -1.0, float("inf")):
        with pytest.raises(InputError, match="rate"):
            subsample(traj, bad)


def test_load_plan_reads_a_trajectory_file_or_plans_a_scenario(tmp_path):
    traj = gaitshift.plan("g1-walk")
    traj.save(tmp_path / "plan.npz")
    from_file = load_plan(tmp_path / "plan.npz")
    from_name = load_plan("g1-walk")
    assert load_plan(traj) is traj
    for other in (from_file, from_name):
        np.testing.assert_allclose(other.com_pos, traj.com_pos, atol=1e-12)
