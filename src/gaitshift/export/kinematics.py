"""MuJoCo forward kinematics of every body of a robot, and the joint and body order of the files.

For each frame (qpos, qvel), after ``mj_kinematics``, ``mj_comPos`` and ``mj_comVel``:

* body pose: ``xpos`` (m, world) and ``xquat`` (w, x, y, z, world) of bodies 1 .. nbody-1 (the world
  body 0 is left out), in MuJoCo body order;
* body velocity at the body frame origin, world frame: angular omega = ``cvel[b, 0:3]`` (rad/s) and
  linear v = ``cvel[b, 3:6]`` + omega x (``xpos[b]`` - ``subtree_com[rootid[b]]``) (m/s), ``cvel`` being
  the velocity of the point of the body at its tree's CoM (``mj_objectVelocity`` would give the
  velocity at the body's CoM ``xipos`` instead, not at its frame origin);
* the whole-body CoM, ``subtree_com`` of the base's tree (m).

The joint order of a robot is that of its MJCF: ``joint_names`` every non-free joint in qpos order,
``actuated_joints`` the joint of each actuator in actuator order (the two agree for every built-in
robot; docs/export.md lists both).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gaitshift.export.resample import continuous_quaternions


def joint_names(model: Any) -> list[str]:
    """Names of the non-free joints of ``model`` in qpos order."""
    import mujoco

    free = int(mujoco.mjtJoint.mjJNT_FREE)
    return [model.joint(j).name for j in range(model.njnt) if int(model.jnt_type[j]) != free]


def actuated_joints(model: Any) -> list[str]:
    """Name of the joint each actuator of ``model`` drives, in actuator order."""
    return [model.joint(int(model.actuator_trnid[a, 0])).name for a in range(model.nu)]


def body_names(model: Any) -> list[str]:
    """Names of the bodies of ``model`` without the world body, in MuJoCo body order."""
    return [model.body(b).name for b in range(1, model.nbody)]


def qpos_columns(model: Any, names: list[str]) -> np.ndarray:
    """qpos address of each named one-coordinate joint (hinge or slide)."""
    return np.array([model.jnt_qposadr[model.joint(n).id] for n in names], dtype=int)


def qvel_columns(model: Any, names: list[str]) -> np.ndarray:
    """qvel address of each named one-coordinate joint (hinge or slide)."""
    return np.array([model.jnt_dofadr[model.joint(n).id] for n in names], dtype=int)


def body_states(model: Any, qpos: np.ndarray, qvel: np.ndarray) -> dict[str, np.ndarray]:
    """Forward kinematics of each frame (see module docstring).

    Returns:
        ``body_pos_w`` (F, B, 3), ``body_quat_w`` (F, B, 4) w x y z, continuous in time per body,
        ``body_lin_vel_w`` (F, B, 3), ``body_ang_vel_w`` (F, B, 3) and ``com`` (F, 3), with
        B = nbody - 1.
    """
    import mujoco

    n, nb = len(qpos), model.nbody - 1
    data = mujoco.MjData(model)
    out = {
        "body_pos_w": np.empty((n, nb, 3)),
        "body_quat_w": np.empty((n, nb, 4)),
        "body_lin_vel_w": np.empty((n, nb, 3)),
        "body_ang_vel_w": np.empty((n, nb, 3)),
        "com": np.empty((n, 3)),
    }
    root = model.body_rootid[1:]
    for k in range(n):
        data.qpos[:] = qpos[k]
        data.qvel[:] = qvel[k]
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        mujoco.mj_comVel(model, data)
        out["body_pos_w"][k] = data.xpos[1:]
        out["body_quat_w"][k] = data.xquat[1:]
        out["com"][k] = data.subtree_com[1]
        ang, lin = data.cvel[1:, 0:3], data.cvel[1:, 3:6]
        out["body_ang_vel_w"][k] = ang
        out["body_lin_vel_w"][k] = lin + np.cross(ang, data.xpos[1:] - data.subtree_com[root])
    out["body_quat_w"] = continuous_quaternions(np.swapaxes(out["body_quat_w"], 0, 1)).swapaxes(0, 1)
    return out


def order_table(robot: Any) -> str:
    """Markdown tables of a robot's joint order (qpos and actuator order) and body order."""
    model = robot.model()
    joints, acts, bodies = joint_names(model), actuated_joints(model), body_names(model)
    same = "the same as" if joints == acts else "NOT the same as"
    lines = [
        f"### {robot.name}",
        "",
        f"{robot.description}. {len(joints)} joints, {len(bodies)} bodies; actuator order is {same} joint order.",
        "",
        "| column | joint (`unitree-csv` col 7+i, `mjlab-npz` `joint_pos[:, i]`) | actuator order |",
        "| --- | --- | --- |",
    ]
    lines += [f"| {i} | `{j}` | `{a}` |" for i, (j, a) in enumerate(zip(joints, acts, strict=False))]
    lines += ["", "| index | body (`mjlab-npz` `body_*_w[:, i]`) |", "| --- | --- |"]
    lines += [f"| {i} | `{b}` |" for i, b in enumerate(bodies)]
    return "\n".join(lines) + "\n"
