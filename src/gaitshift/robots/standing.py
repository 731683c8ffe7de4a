"""A standing pose computed by IK for a nominal CoM height, for robot YAMLs that give none.

With the base upright at the origin, the leg joints q_L (n) solve, in the least-squares sense
(Levenberg-Marquardt, joint ranges enforced by clipping),

    R_sole,i(q) = I                    each sole flat and straight ahead (3 equations per sole;
                                       roll dropped on a leg that cannot roll its foot)
    y_sole,i(q) = y_sole,i(q0)         soles at the lateral positions of the model's qpos0
    z_L(q) = z_R(q),  x_L(q) = x_R(q)  soles side by side on one plane
    x_com(q) = (x_L + x_R) / 2         CoM over the middle of the soles
    z_com(q) - z_L(q) = h              the CoM height above the soles, m

starting from the knees bent by :data:`KNEE_GUESS` rad toward their larger range. Joints that are not
leg joints stay at qpos0.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gaitshift.errors import InputError

#: first guess of the knee angle, rad (toward the larger side of the knee's range)
KNEE_GUESS = 0.6


def _rot_err(R: np.ndarray) -> np.ndarray:
    """Small-angle rotation vector w of R = exp([w]) (world frame, rad, (3,)); its rate is the angular
    velocity, so its Jacobian is the rotational Jacobian of the frame."""
    return 0.5 * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])


def guess_qpos(model: Any, knees: list[int]) -> np.ndarray:
    """qpos0 with the base upright at the origin and the ``knees`` bent by :data:`KNEE_GUESS` rad toward
    the larger side of their range (positive when unlimited), (nq,)."""
    q = np.asarray(model.qpos0, float).copy()
    q[:3], q[3:7] = 0.0, (1.0, 0.0, 0.0, 0.0)
    for k in knees:
        lo, hi = model.jnt_range[k] if model.jnt_limited[k] else (-np.inf, np.inf)
        q[model.jnt_qposadr[k]] = KNEE_GUESS if hi >= -lo else -KNEE_GUESS
    return q


def computed_standing_pose(
    model: Any, sites: tuple[int, int], legs: list[list[int]], knees: list[int], roll: list[bool], height: float
) -> dict[str, float]:
    """Leg joint angles {name: rad} of the standing pose with the CoM ``height`` m above the soles.

    Raises:
        InputError: no pose reaches ``height`` with flat soles (residual above 0.1 mm).

    Args:
        model: the model with the sole sites; sites: their ids (left, right).
        legs: joint ids of each leg; knees: the knee joint ids; roll: whether each leg can roll its foot.
        height: CoM height above the soles, m.
    """
    import mujoco

    d = mujoco.MjData(model)
    q = guess_qpos(model, knees)
    d.qpos[:] = q
    mujoco.mj_kinematics(model, d)
    y0 = [float(d.site_xpos[s][1]) for s in sites]
    joints = [j for leg in legs for j in leg]
    qadr = np.array([model.jnt_qposadr[j] for j in joints])
    dofs = np.array([model.jnt_dofadr[j] for j in joints])
    rng = np.array([model.jnt_range[j] if model.jnt_limited[j] else (-np.inf, np.inf) for j in joints])
    jp, jr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    for _ in range(100):
        d.qpos[:] = q
        mujoco.mj_kinematics(model, d)
        mujoco.mj_comPos(model, d)
        P, J = [], []
        for i, s in enumerate(sites):
            mujoco.mj_jacSite(model, d, jp, jr, s)
            P.append((d.site_xpos[s].copy(), jp[:, dofs].copy()))
            R = d.site_xmat[s].reshape(3, 3)
            rows = (0, 1, 2) if roll[i] else (1, 2)
            J.append((_rot_err(R)[list(rows)], jr[list(rows)][:, dofs].copy()))
        mujoco.mj_jacSubtreeCom(model, d, jp, 1)
        com, Jc = d.subtree_com[1].copy(), jp[:, dofs].copy()
        (pl, Jl), (pr, Jr) = P
        r = np.concatenate(
            [
                J[0][0],
                J[1][0],
                [pl[1] - y0[0], pr[1] - y0[1], pl[2] - pr[2], pl[0] - pr[0]],
                [com[0] - (pl[0] + pr[0]) / 2, com[2] - pl[2] - height],
            ]
        )
        A = np.vstack(
            [J[0][1], J[1][1], Jl[1], Jr[1], Jl[2] - Jr[2], Jl[0] - Jr[0], Jc[0] - (Jl[0] + Jr[0]) / 2, Jc[2] - Jl[2]]
        )
        if np.max(np.abs(r)) < 1e-9:
            break
        dq = np.linalg.solve(A.T @ A + 1e-6 * np.eye(len(joints)), -A.T @ r)
        q[qadr] = np.clip(q[qadr] + dq, rng[:, 0], rng[:, 1])
    if np.max(np.abs(r)) > 1e-4:
        raise InputError(
            "robot.com_height",
            round(height, 4),
            f"a reachable standing CoM height (IK residual {np.max(np.abs(r)):.2g})",
        )
    return {model.joint(j).name: float(q[model.jnt_qposadr[j]]) for j in joints}
