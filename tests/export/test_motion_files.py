"""The exported motion files, read back with numpy and judged by MuJoCo alone (no gaitshift export code):

* forward kinematics of the exported root and joints (a plain model compiled from the robot's MJCF)
  reproduces the exported body poses (``mjlab-npz``) and the ``unitree-csv`` rows give the same
  bodies as the npz at the same rate, for the G1 and the T1;
* the motion is the source's: the whole-body CoM of each frame is the plan's CoM (or the simulation's
  logged CoM) at the frame time;
* the exported velocities (joints, body linear and angular) match central differences of the
  exported positions and orientations, and the same check rejects angular velocities given in the
  body frame instead of the world frame; on the simulation they are the velocities the robot had
  (the logged, measured qvel at the frame times);
* every quaternion is unit and continuous (consecutive dot products > 0), root quaternion of the CSV
  included.
"""

from __future__ import annotations

import functools
import json

import mujoco
import numpy as np
import pytest

from gaitshift.robots import load_robot

SOURCES = ["g1-plan", "t1-plan", "g1-sim"]
ROBOT = {"g1-plan": "g1", "t1-plan": "t1", "g1-sim": "g1"}


@functools.cache
def plain_model(robot: str) -> mujoco.MjModel:
    """The robot's MJCF compiled as shipped (no gaitshift additions)."""
    return mujoco.MjModel.from_xml_path(str(load_robot(robot).mjcf))


def fk(model, root_pos, root_quat_wxyz, joints, joint_adr):
    """Body positions (F, B, 3), quaternions (F, B, 4) and whole-body CoM (F, 3) of each frame."""
    d = mujoco.MjData(model)
    n = len(root_pos)
    pos, quat, com = np.empty((n, model.nbody - 1, 3)), np.empty((n, model.nbody - 1, 4)), np.empty((n, 3))
    for k in range(n):
        d.qpos[:3], d.qpos[3:7], d.qpos[joint_adr] = root_pos[k], root_quat_wxyz[k], joints[k]
        mujoco.mj_kinematics(model, d)
        pos[k], quat[k] = d.xpos[1:], d.xquat[1:]
        com[k] = (model.body_mass[:, None] * d.xipos).sum(0) / model.body_mass.sum()
    return pos, quat, com


def rotation_angle(q0, q1):
    """Angle (rad) between the rotations of unit quaternions (..., 4)."""
    return 2 * np.arccos(np.clip(np.abs(np.sum(q0 * q1, axis=-1)), 0, 1))


def npz_fk(path, robot):
    z = np.load(path, allow_pickle=False)
    m = plain_model(robot)
    names = [str(n) for n in z["joint_names"]]
    adr = [m.jnt_qposadr[m.joint(n).id] for n in names]
    return z, fk(m, z["body_pos_w"][:, 0], z["body_quat_w"][:, 0], z["joint_pos"], adr)


@pytest.mark.parametrize("source", SOURCES)
def test_fk_of_the_npz_root_and_joints_reproduces_every_body_pose(source, exported):
    robot = ROBOT[source]
    z, (pos, quat, _) = npz_fk(exported(source, "mjlab-npz"), robot)
    m = plain_model(robot)
    assert int(z["fps"][0]) == 50 and z["fps"].shape == (1,)
    assert [str(b) for b in z["body_names"]] == [m.body(b).name for b in range(1, m.nbody)]
    assert z["joint_pos"].shape[1] == m.nq - 7 == z["joint_vel"].shape[1]
    assert np.abs(pos - z["body_pos_w"]).max() < 1e-9
    assert rotation_angle(quat, z["body_quat_w"]).max() < 1e-6
    assert z["body_pos_w"][:, :, 2].min() > -0.01  # nothing below the floor


@pytest.mark.parametrize("source", SOURCES)
def test_csv_rows_give_the_same_bodies_as_the_npz_at_the_same_rate(source, exported):
    robot = ROBOT[source]
    m = plain_model(robot)
    rows = np.loadtxt(exported(source, "unitree-csv", 50), delimiter=",")
    assert rows.shape[1] == 7 + m.nu
    adr = [m.jnt_qposadr[m.actuator_trnid[a, 0]] for a in range(m.nu)]  # MJCF actuator order
    pos, quat, _ = fk(m, rows[:, :3], rows[:, [6, 3, 4, 5]], rows[:, 7:], adr)
    z = np.load(exported(source, "mjlab-npz"))  # mjlab's one rate, 50 Hz
    assert len(rows) == len(z["body_pos_w"]) and int(z["fps"][0]) == 50
    assert np.abs(pos - z["body_pos_w"]).max() < 1e-6
    assert rotation_angle(quat, z["body_quat_w"]).max() < 1e-6
    assert np.all(np.sum(rows[1:, 3:7] * rows[:-1, 3:7], axis=1) > 0)  # CSV root quaternion continuous


@pytest.mark.parametrize("source", SOURCES)
def test_the_exported_motion_is_the_source_motion(source, exported, motions):
    _, (_, _, com) = npz_fk(exported(source, "mjlab-npz"), ROBOT[source])
    src = np.load(motions[source])
    t = src["t"][0] + np.arange(len(com)) / 50.0
    ref = np.stack([np.interp(t, src["t"], src["com_pos"][:, i]) for i in range(3)], axis=1)
    assert np.linalg.norm(com - ref, axis=1).max() < 1e-3
    assert t[-1] > src["t"][-1] - 1 / 50.0  # the whole motion, not a part


def central_difference_errors(z, ang=None):
    """|velocity - central difference| per frame (1 .. F-2) for joints, body linear and angular
    velocity, with the angular one from q_{k+1} q_{k-1}^-1 (world frame)."""
    dt = 1.0 / int(z["fps"][0])
    jp, bp, bq = z["joint_pos"], z["body_pos_w"], z["body_quat_w"]
    ang = z["body_ang_vel_w"] if ang is None else ang
    e_joint = np.abs((jp[2:] - jp[:-2]) / (2 * dt) - z["joint_vel"][1:-1])
    e_lin = np.linalg.norm((bp[2:] - bp[:-2]) / (2 * dt) - z["body_lin_vel_w"][1:-1], axis=-1)
    w1, v1 = bq[2:, ..., 0], bq[2:, ..., 1:]
    w0, v0 = bq[:-2, ..., 0], -bq[:-2, ..., 1:]
    rw = w1 * w0 - np.sum(v1 * v0, axis=-1)
    rv = w1[..., None] * v0 + w0[..., None] * v1 + np.cross(v1, v0)
    s = np.linalg.norm(rv, axis=-1)
    omega = rv * (2 * np.arctan2(s, np.abs(rw)) * np.sign(rw + (rw == 0)) / np.maximum(s, 1e-12))[..., None]
    e_ang = np.linalg.norm(omega / (2 * dt) - ang[1:-1], axis=-1)
    return {"joint": e_joint, "linear": e_lin, "angular": e_ang}


#: bounds on the median, the 95th percentile and the maximum of |v - central difference| at 50 fps
#: (rad/s or m/s): joint velocities are the central differences of the frames; body velocities come
#: from MuJoCo's Jacobians at each frame, equal to the differences of the FK poses up to O(h^2) terms
MEDIAN, P95, MAX = 0.005, 0.03, 0.5


@pytest.mark.parametrize("source", SOURCES)
def test_exported_velocities_match_central_differences_of_the_exported_poses(source, exported):
    z = np.load(exported(source, "mjlab-npz"))
    for group, e in central_difference_errors(z).items():
        assert np.median(e) < MEDIAN, group
        assert np.percentile(e, 95) < P95, group
        assert e.max() < MAX, group
    # the same check rejects the angular velocity expressed in each body's frame instead of the world
    R = np.zeros((*z["body_quat_w"].shape[:2], 3, 3))
    d = mujoco.MjData(plain_model(ROBOT[source]))
    for idx in np.ndindex(*R.shape[:2]):
        mujoco.mju_quat2Mat(d.xmat[0], z["body_quat_w"][idx])
        R[idx] = d.xmat[0].reshape(3, 3)
    local = np.einsum("fbji,fbj->fbi", R, z["body_ang_vel_w"])
    assert np.percentile(central_difference_errors(z, ang=local)["angular"], 95) > P95


def test_the_simulation_export_has_the_velocities_the_robot_had(exported, motions):
    z, log = np.load(exported("g1-sim", "mjlab-npz")), np.load(motions["g1-sim"])
    t = log["t"][0] + np.arange(len(z["joint_pos"])) / 50.0
    names = [str(n) for n in z["joint_names"]]
    m = plain_model("g1")
    measured = np.stack([np.interp(t, log["t"], log["qvel"][:, m.jnt_dofadr[m.joint(n).id]]) for n in names], 1)
    e = np.abs(measured - z["joint_vel"])
    assert np.median(e) < 0.005 and np.percentile(e, 90) < 0.05  # impacts: a few frames differ more
    base = np.stack([np.interp(t, log["t"], log["qvel"][:, i]) for i in range(3)], 1)  # world frame
    e = np.linalg.norm(base - z["body_lin_vel_w"][:, 0], axis=1)
    assert np.median(e) < 0.01 and np.percentile(e, 90) < 0.02


@pytest.mark.parametrize("source", SOURCES)
def test_quaternions_are_unit_and_continuous(source, exported):
    q = np.load(exported(source, "mjlab-npz"))["body_quat_w"]
    assert np.abs(np.linalg.norm(q, axis=-1) - 1).max() < 1e-9
    assert np.sum(q[1:] * q[:-1], axis=-1).min() > 0.9  # no sign flip, and no jump at 50 fps


def test_the_log_export_says_what_it_holds(exported):
    z = np.load(exported("g1-sim", "mjlab-npz"), allow_pickle=False)
    keys = {"fps", "joint_pos", "joint_vel", "body_pos_w", "body_quat_w", "body_lin_vel_w", "body_ang_vel_w"}
    assert keys <= set(z.files)
    assert all(np.all(np.isfinite(z[k])) for k in keys)
    assert json.dumps([str(n) for n in z["joint_names"]]).count("joint") == 29
