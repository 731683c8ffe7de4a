"""Independent forward-kinematics checks of joint trajectories with plain MuJoCo (no gaitshift code).

The whole-body CoM is recomputed as the mass-weighted mean of the body CoMs (``xipos``, ``body_mass``),
never from ``subtree_com``; a sole is the pose of its body plus the sole offset of the robot YAML.
Shared by the whole-body IK tests and the closed-loop tests.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np


def body_com(model, data):
    """Whole-body CoM (3,) from the body CoMs of ``data`` after ``mj_kinematics``."""
    mass = model.body_mass[1:]
    return (mass[:, None] * data.xipos[1:]).sum(0) / mass.sum()


def sole_poses(model, data, bodies, offsets):
    """[(centre (3,), rotation (3, 3))] of each sole: the pose of body ``bodies[i]`` (names) with the
    point ``offsets[i]`` (3,) of its frame, after ``mj_kinematics``."""
    out = []
    for body, offset in zip(bodies, offsets, strict=True):
        b = model.body(body).id
        r = data.xmat[b].reshape(3, 3)
        out.append((data.xpos[b] + r @ np.asarray(offset, float), r.copy()))
    return out


def forward_kinematics(model, qpos, bodies, offsets):
    """CoM (N, 3), sole centres (N, 2, 3), sole rotations (N, 2, 3, 3) of configurations ``qpos`` (N, nq)."""
    data = mujoco.MjData(model)
    n = len(qpos)
    com, centre, rot = np.zeros((n, 3)), np.zeros((n, 2, 3)), np.zeros((n, 2, 3, 3))
    for k in range(n):
        data.qpos[:] = qpos[k]
        mujoco.mj_kinematics(model, data)
        com[k] = body_com(model, data)
        for side, (c, r) in enumerate(sole_poses(model, data, bodies, offsets)):
            centre[k, side], rot[k, side] = c, r
    return com, centre, rot


def robot_fk(robot, qpos):
    """:func:`forward_kinematics` on a plain model of the robot config's MJCF with its sole offsets."""
    model = mujoco.MjModel.from_xml_path(str(robot.mjcf))
    return forward_kinematics(model, qpos, robot.sole_bodies, robot.sole_offsets)


def tilt(rot):
    """Angle (rad) between the z axis of each rotation (..., 3, 3) and the world z axis."""
    return np.arctan2(np.hypot(rot[..., 0, 2], rot[..., 1, 2]), rot[..., 2, 2])


def yaw(rot):
    """Heading (rad) of the x axis of each rotation (..., 3, 3) in the ground plane."""
    return np.arctan2(rot[..., 1, 0], rot[..., 0, 0])


def angle_diff(a, b):
    """a - b wrapped to [-pi, pi)."""
    return (np.asarray(a) - np.asarray(b) + math.pi) % (2 * math.pi) - math.pi
