"""The motor torques that hold a pose still with both soles on the ground: the stand-up's feed-forward.

At rest (``qvel = 0``) the equations of motion reduce to ``qfrc_bias = J^T w + [0; tau]``: gravity is
carried by the two soles' wrenches ``w`` (6 each, at the sole centres) and the motors' torques ``tau``. The
six rows of the floating base fix ``w`` (the least-norm wrenches that carry the weight); the motor rows then
give ``tau = qfrc_bias[motors] - J[:, motors]^T w``. With a PD on the joint targets, this feed-forward
leaves the PD only the errors to correct, so that moderate gains stand the robot up without sagging.
"""

import mujoco
import numpy as np

from gaitshift.robots.model import RobotModel

__all__ = ["standing_torques"]


def standing_torques(robot: RobotModel, qpos: np.ndarray) -> np.ndarray:
    """The torques (nu,) N m, motor order, that hold ``qpos`` (nq,) at rest on both soles (module docstring)."""
    m = robot.model
    d = mujoco.MjData(m)
    d.qpos[:] = qpos
    mujoco.mj_forward(m, d)
    rows = []
    for side in (0, 1):
        centre, _ = robot.sole_frame(d, side)
        jacp, jacr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
        mujoco.mj_jac(m, d, jacp, jacr, centre, robot.soles[side].body)
        rows += [jacp, jacr]
    J = np.vstack(rows)  # (12, nv)
    bias = d.qfrc_bias.copy()
    w = np.linalg.lstsq(J[:, :6].T, bias[:6], rcond=None)[0]
    dofs = np.asarray(robot.actuated_dofs)
    tau: np.ndarray = bias[dofs] - J[:, dofs].T @ w
    return tau
