"""The initial configuration of a run: standing on the plan's first footholds with its first CoM."""

from __future__ import annotations

import mujoco
import numpy as np

from gaitshift.common.rotations import rot_z
from gaitshift.control.qp_terms import rotation_error
from gaitshift.errors import InputError
from gaitshift.robots.model import RobotModel, standing_qpos

#: leg flexions tried for the first guess: factors on the standing pose's leg joint angles
FLEXIONS = np.linspace(0.2, 1.8, 17)


def _leg_flexion_guess(plant: RobotModel, d: mujoco.MjData, com: np.ndarray) -> np.ndarray:
    """The standing pose whose leg flexion (:func:`~gaitshift.robots.model.standing_qpos`, factors
    :data:`FLEXIONS`) puts the CoM nearest to the height ``com[2]``, moved horizontally under ``com``: (nq,)."""
    m = plant.model
    best = None
    for flexion in FLEXIONS:
        qb = standing_qpos(plant, flexion=float(flexion))
        d.qpos[:] = qb
        mujoco.mj_kinematics(m, d)
        mujoco.mj_comPos(m, d)
        gap = abs(d.subtree_com[0][2] - com[2])
        if best is None or gap < best[0]:
            best = (gap, qb, d.subtree_com[0].copy())
    assert best is not None
    q = best[1]
    q[0] += com[0] - best[2][0]
    q[1] += com[1] - best[2][1]
    return q


def initial_qpos(
    plant: RobotModel, com: np.ndarray, feet: np.ndarray, yaws: np.ndarray, iters: int = 200
) -> np.ndarray:
    """Standing configuration (nq,) with sole centres at ``feet`` (2, 3) m, flat with yaw ``yaws`` (2,)
    rad, the CoM at ``com`` (3,) m and the pelvis upright with the mean yaw: damped Gauss-Newton on
    these 15 equations (+ 3 for the pelvis), regularised toward the initial guess's joint angles. On a
    leg that cannot roll its foot (``RobotConfig.foot_roll``), the sole's roll is left free.

    Raises:
        InputError: the pose is out of reach (residual above 2 mm).
    """
    m = plant.model
    d = mujoco.MjData(m)
    q = _leg_flexion_guess(plant, d, com)
    q_post = q.copy()
    jp, jr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
    err = np.inf
    for _ in range(iters):
        d.qpos[:] = q
        mujoco.mj_kinematics(m, d)
        mujoco.mj_comPos(m, d)
        rows, res = [], []
        for s in (0, 1):
            c, R = plant.sole_frame(d, s)
            mujoco.mj_jac(m, d, jp, jr, c, plant.soles[s].body)
            keep = np.eye(3) if plant.robot.foot_roll[s] else R[:, 1:].T  # (3 or 2, 3) rotation rows kept
            rows += [jp.copy(), keep @ jr]
            res += [feet[s] - c, keep @ rotation_error(rot_z(yaws[s]), R)]
        mujoco.mj_jacSubtreeCom(m, d, jp, 0)
        rows.append(jp.copy())
        res.append(com - d.subtree_com[0])
        n_task = sum(len(x) for x in res)
        mujoco.mj_jacBody(m, d, jp, jr, plant.pelvis_body)
        rows.append(jr.copy())
        res.append(rotation_error(rot_z(float(np.mean(yaws))), d.xmat[plant.pelvis_body].reshape(3, 3)))
        J = np.vstack(rows)
        r = np.concatenate(res)
        err = float(np.max(np.abs(r[:n_task])))
        if err < 1e-7:
            break
        dq_post = np.zeros(m.nv)
        dq_post[6:] = q_post[7:] - q[7:]
        A = J.T @ J + 1e-4 * np.eye(m.nv)
        dq = np.linalg.solve(A, J.T @ r + 1e-5 * dq_post)
        mujoco.mj_integratePos(m, q, dq, 1.0)
    if err > 2e-3:
        raise InputError("scenario", "initial stance", f"a reachable standing pose (IK residual {err * 1e3:.1f} mm)")
    return q


def sensed_start(plant: RobotModel, qpos0: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The start state (nq,) of a robot standing still on a level floor, from its encoders ``q`` (nu,) rad
    (motor order) and the planned start ``qpos0`` (nq,): the joints as measured; the base turned by the
    least rotation that makes the soles' mean normal vertical (the plan's heading kept); the base moved
    up or down so that the lowest sole point is as high as in ``qpos0``, its horizontal place kept.

    A world that puts the robot exactly at ``qpos0`` gets ``qpos0`` back (to its encoders' noise); a robot
    that stood itself up (the brain's stand-up over DDS) gets the pelvis tilt its legs measure instead of
    the plan's: on the G1 the stand-up leaves the pelvis 0.03 rad from the plan's tilt (docs/deploy.md).

    .. math::

        n = \\frac{R_{s,0} e_z + R_{s,1} e_z}{\\lVert R_{s,0} e_z + R_{s,1} e_z \\rVert},\\qquad
        R_{base} \\leftarrow \\mathrm{Rot}(n \\times e_z, \\angle(n, e_z))\\, R_{base}
    """
    m = plant.model
    d = mujoco.MjData(m)
    dofs = np.asarray(plant.actuated_dofs)
    out = np.array(qpos0, float)
    out[m.jnt_qposadr[m.dof_jntid[dofs]]] = q
    d.qpos[:] = qpos0
    mujoco.mj_kinematics(m, d)
    floor = min(float(plant.contact_points(d, s)[:, 2].min()) for s in (0, 1))
    d.qpos[:] = out
    mujoco.mj_kinematics(m, d)
    n = plant.sole_frame(d, 0)[1][:, 2] + plant.sole_frame(d, 1)[1][:, 2]
    n /= np.linalg.norm(n)
    axis = np.cross(n, [0.0, 0.0, 1.0])
    turn = np.zeros(4)
    angle = float(np.arctan2(np.linalg.norm(axis), n[2]))
    mujoco.mju_axisAngle2Quat(turn, axis / max(float(np.linalg.norm(axis)), 1e-12), angle)
    mujoco.mju_mulQuat(out[3:7], turn, out[3:7].copy())
    d.qpos[:] = out
    mujoco.mj_kinematics(m, d)
    out[2] += floor - min(float(plant.contact_points(d, s)[:, 2].min()) for s in (0, 1))
    return out
