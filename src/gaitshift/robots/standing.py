"""A standing pose computed by IK for a nominal CoM height, for robot YAMLs that give none.

With the base upright at the origin, the leg joints q_L (n) solve, in the least-squares sense
(Levenberg-Marquardt, joint ranges enforced by clipping),

    R_sole,i(q) = I                    each sole flat and straight ahead (3 equations per sole;
                                       roll dropped on a leg that cannot roll its foot)
    y_sole,i(q) = y_sole,i(q0)         soles at the lateral positions of the model's qpos0
    z_L(q) = z_R(q),  x_L(q) = x_R(q)  soles side by side on one plane
    x_com(q) = (x_L + x_R) / 2         CoM over the middle of the soles
    z_com(q) - z_L(q) = h              the CoM height above the soles, m

starting from the knees bent by :data:`KNEE_GUESS` rad toward their larger range. Joints given in the
YAML's ``standing_pose`` (``held``: arms only, no leg joint) keep their values and are not solved
for; the other joints that are not leg joints stay at qpos0.

A sole frame that no leg motion turns flat (a foot link rotated against the world with
``sole_orientation: body``) leaves the soles tilted by more than :data:`SOLE_TILT_TOL`: the error then
names ``sole_orientation``, not the height.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gaitshift.errors import InputError

#: first guess of the knee angle, rad (toward the larger side of the knee's range)
KNEE_GUESS = 0.6
#: a sole left tilted by more than this (rad) when the IK stops has a wrong frame, not a wrong height
SOLE_TILT_TOL = 0.05


def _rot_err(R: np.ndarray) -> np.ndarray:
    """Small-angle rotation vector w of R = exp([w]) (world frame, rad, (3,)); its rate is the angular
    velocity, so its Jacobian is the rotational Jacobian of the frame."""
    return 0.5 * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])


def guess_qpos(model: Any, knees: list[int], held: dict[str, float] | None = None) -> np.ndarray:
    """qpos0 with the base upright at the origin, the ``knees`` bent by :data:`KNEE_GUESS` rad toward
    the larger side of their range (positive when unlimited) and the ``held`` joints {name: rad} at
    their values, (nq,)."""
    q = np.asarray(model.qpos0, float).copy()
    q[:3], q[3:7] = 0.0, (1.0, 0.0, 0.0, 0.0)
    for k in knees:
        lo, hi = model.jnt_range[k] if model.jnt_limited[k] else (-np.inf, np.inf)
        q[model.jnt_qposadr[k]] = KNEE_GUESS if hi >= -lo else -KNEE_GUESS
    for name, angle in (held or {}).items():
        q[model.jnt_qposadr[model.joint(name).id]] = angle
    return q


def _tilt(R: np.ndarray) -> float:
    """Angle of a frame's z axis from the vertical, rad."""
    return float(np.arccos(np.clip(R[2, 2], -1.0, 1.0)))


def computed_standing_pose(
    model: Any,
    sites: tuple[int, int],
    legs: list[list[int]],
    knees: list[int],
    roll: list[bool],
    height: float,
    held: dict[str, float] | None = None,
    orientation: object = "body",
) -> dict[str, float]:
    """Angles {name: rad} of the standing pose with the CoM ``height`` m above the soles: the ``held``
    joints as given, the other leg joints solved.

    Raises:
        InputError: no pose reaches ``height`` with flat soles (residual above 0.1 mm), naming
            ``sole_orientation`` (the YAML value ``orientation``) when a sole stays tilted by more than
            :data:`SOLE_TILT_TOL`, else ``com_height``.

    Args:
        model: the model with the sole sites; sites: their ids (left, right).
        legs: joint ids of each leg; knees: the knee joint ids; roll: whether each leg can roll its foot.
        height: CoM height above the soles, m.
        held: joints {name: rad} given by the YAML's ``standing_pose``, kept.
        orientation: the YAML's ``sole_orientation`` (for the error message).
    """
    import mujoco

    held = dict(held or {})
    d = mujoco.MjData(model)
    q = guess_qpos(model, [k for k in knees if model.joint(k).name not in held], held)
    d.qpos[:] = q
    mujoco.mj_kinematics(model, d)
    y0 = [float(d.site_xpos[s][1]) for s in sites]
    joints = [j for leg in legs for j in leg if model.joint(j).name not in held]
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
        raise _unreached(d, sites, float(np.max(np.abs(r))), height, orientation)
    return held | {model.joint(j).name: float(q[model.jnt_qposadr[j]]) for j in joints}


def _unreached(d: Any, sites: tuple[int, int], residual: float, height: float, orientation: object) -> InputError:
    """The error of a standing pose the IK did not reach (residual, m or rad): ``sole_orientation`` when a
    sole stays tilted by more than :data:`SOLE_TILT_TOL` (the legs cannot turn it flat), else ``com_height``."""
    tilts = [_tilt(d.site_xmat[s].reshape(3, 3)) for s in sites]
    if max(tilts) > SOLE_TILT_TOL:
        side = "left" if tilts[0] >= tilts[1] else "right"
        return InputError(
            "robot.sole_orientation",
            orientation,
            f"a sole frame the legs can turn flat (the {side} sole's normal stays "
            f"{np.degrees(max(tilts)):.1f} deg from vertical; set sole_orientation: geoms, or a "
            "quaternion per side)",
        )
    return InputError(
        "robot.com_height",
        round(height, 4),
        f"a reachable standing CoM height (IK residual {residual:.2g})",
    )
