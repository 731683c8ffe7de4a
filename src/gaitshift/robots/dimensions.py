"""What a robot's model measures about its legs: CoM height, foot separation, leg length, foot roll (SI units).

Each runs MuJoCo's kinematics on a fresh ``MjData`` of the compiled model (with the sole sites of
:func:`gaitshift.robots.mjcf.add_sole_sites`), base upright:

* CoM height: height of the whole-body CoM (``subtree_com`` of the first body under the world) above
  the mean height of the two sole centres, in a standing pose;
* foot separation: lateral distance |y_L - y_R| of the two sole centres in that pose;
* leg length: distance from the hip-pitch joint axis (``xanchor``) to the sole centre with every joint
  at its ``qpos0`` value (leg straight), the shorter of the two legs;
* foot roll: whether each leg can roll its foot about the sole's x axis, knees bent (:func:`foot_roll`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gaitshift.robots import mjcf as _mj
from gaitshift.robots.standing import guess_qpos


def standing_data(model: Any, pose: tuple[tuple[str, float], ...]) -> tuple[Any, np.ndarray]:
    """``MjData`` of ``model`` in ``pose`` (joint name, angle rad) after ``mj_kinematics`` and
    ``mj_comPos``, and the two sole centres (2, 3) m."""
    import mujoco  # imported on use, like the rest of robots/

    data = mujoco.MjData(model)
    data.qpos[:] = _mj.standing_qpos(model, pose)
    mujoco.mj_kinematics(model, data)
    mujoco.mj_comPos(model, data)
    return data, np.array([data.site(s).xpos for s in _mj.SOLE_SITES])


def com_height(model: Any, pose: tuple[tuple[str, float], ...]) -> float:
    """CoM height above the mean sole height in ``pose`` (base upright), m."""
    data, soles = standing_data(model, pose)
    return float(data.subtree_com[1][2] - soles[:, 2].mean())


def foot_separation(model: Any, pose: tuple[tuple[str, float], ...]) -> float:
    """Lateral distance between the two sole centres in ``pose``, m."""
    _, soles = standing_data(model, pose)
    return float(abs(soles[0, 1] - soles[1, 1]))


def leg_length(model: Any, hips: tuple[str, str]) -> float:
    """Shortest hip-pitch-axis-to-sole distance of the two legs (hip-pitch joints ``hips``, left then
    right) with every joint at 0, m."""
    import mujoco

    data = mujoco.MjData(model)
    data.qpos[:] = model.qpos0
    data.qpos[3:7] = (1.0, 0.0, 0.0, 0.0)
    mujoco.mj_kinematics(model, data)
    legs = []
    for side, hip in enumerate(hips):
        anchor = data.xanchor[model.joint(hip).id]
        legs.append(float(np.linalg.norm(anchor - data.site(_mj.SOLE_SITES[side]).xpos)))
    return min(legs)


def foot_roll(
    model: Any, legs: list[list[int]], knees: list[int], soles: tuple[Any, Any], bodies: list[int]
) -> tuple[bool, bool]:
    """Whether each leg can roll its foot about the sole's x axis without moving the sole centre: the
    sole twist (0, x_sole) is in the range of the leg's (6, n) Jacobian, knees bent (base fixed).
    ``legs``: per leg its joint ids; ``knees``: the knee joint ids; ``soles``: the
    :class:`~gaitshift.robots.soles.SoleGeometry` pair; ``bodies``: the foot body ids (5-DOF legs such as
    the H1's cannot)."""
    import mujoco

    d = mujoco.MjData(model)
    d.qpos[:] = guess_qpos(model, knees)
    mujoco.mj_kinematics(model, d)
    mujoco.mj_comPos(model, d)
    jp, jr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    out = []
    for leg, sole, b in zip(legs, soles, bodies, strict=True):
        R = d.xmat[b].reshape(3, 3)
        mujoco.mj_jac(model, d, jp, jr, d.xpos[b] + R @ sole.centre, b)
        dofs = [int(model.jnt_dofadr[j]) for j in leg]
        J = np.vstack([jp[:, dofs], jr[:, dofs]])
        target = np.concatenate([np.zeros(3), R @ sole.rotation[:, 0]])
        dq = np.linalg.lstsq(J, target, rcond=None)[0]
        out.append(bool(np.linalg.norm(J @ dq - target) < 1e-6))
    return out[0], out[1]
