"""Checks of a plan against a robot before any simulation: joint speeds against the YAML's limits.

The whole-body IK (:mod:`gaitshift.wholebody.ik`) is solved at :data:`CHECK_RATE` Hz (the joint speeds
are its central differences on the configuration manifold), and the peak |q̇_j| of every joint with a
limit in the robot YAML (``velocity_limits``) is compared with it. Sampling at 100 Hz underestimates
a peak by O((ω Δt)^2) for a motion of angular frequency ω: < 2 % for steps of 0.3 s and longer.
"""

from __future__ import annotations

import numpy as np

from gaitshift.errors import InfeasibleError
from gaitshift.robots.config import RobotConfig
from gaitshift.trajectory.contract import Trajectory

#: IK rate of the joint-speed check, Hz (rounded to 1/(k dt) of the plan)
CHECK_RATE = 100.0


class JointSpeedError(InfeasibleError):
    """A joint of the robot would move faster than its limit (message names joint, peak and limit)."""


def peak_joint_speeds(robot: RobotConfig, traj: Trajectory) -> np.ndarray | None:
    """Peak |q̇| (J,) rad/s of every joint of ``robot.joint_names`` along ``traj``, or None when the IK
    cannot follow the plan (``gaitshift robot check`` reports why)."""
    from gaitshift.wholebody.ik import IKInfeasibleError, IKSettings, WholeBodyIK

    k = max(1, round(1.0 / (CHECK_RATE * traj.dt)))
    ik = WholeBodyIK(robot, IKSettings())
    try:
        joints = ik.solve(traj, 1.0 / (k * traj.dt), check_velocities=False)
    except IKInfeasibleError:
        return None
    vadr = np.array([robot.model().jnt_dofadr[robot.model().joint(n).id] for n in robot.joint_names])
    peak: np.ndarray = np.max(np.abs(joints.qvel[:, vadr]), axis=0)
    return peak


def check_joint_speeds(robot: RobotConfig, traj: Trajectory) -> None:
    """Raise :class:`JointSpeedError` naming the joint, its peak speed and its limit when the plan's
    whole-body motion exceeds a ``velocity_limits`` entry of the robot YAML; nothing without limits.

    Raises:
        JointSpeedError: the worst joint over its limit.
    """
    if not np.any(np.isfinite(robot.velocity_limit)):
        return
    peak = peak_joint_speeds(robot, traj)
    if peak is None:
        return
    ratio = peak / robot.velocity_limit
    j = int(np.argmax(ratio))
    if ratio[j] > 1.0:
        raise JointSpeedError(
            f"{robot.name}: joint {robot.joint_names[j]} needs {peak[j]:.2f} rad/s, above its limit "
            f"{robot.velocity_limit[j]:.2f} rad/s (velocity_limits); slow the plan down (longer "
            "steps) or "
            "use a lower CoM height"
        )
