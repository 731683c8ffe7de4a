"""Whole-body layer on real humanoids: robot configs, scenario scaling, whole-body IK, video.

Public API::

    from gaitshift.robot import load_robot, scale_scenario, wholebody, render_video
    g1 = load_robot("g1")                       # RobotConfig (Unitree G1 MJCF, limits from the model)
    sc = scale_scenario("paper001-table2-walk-run-walk", g1)
    joints = wholebody(gaitshift.plan(sc), g1, rate=500)   # JointTrajectory: t, qpos, qvel, meta
    joints.save("joints.npz")

The IK and the renderer import mujoco and mink lazily (the ``robot`` extra).
"""

from __future__ import annotations

from typing import Any

from .config import RobotConfig, builtin_robots, load_robot
from .scaling import scale_factor, scale_scenario

__all__ = ["IKSettings", "JointTrajectory", "RobotConfig", "WholeBodyIK", "builtin_robots", "load_robot",
           "render_video", "scale_factor", "scale_scenario", "wholebody"]


def __getattr__(name: str) -> Any:
    if name in ("IKSettings", "JointTrajectory", "WholeBodyIK", "wholebody"):
        from . import ik

        return getattr(ik, name)
    if name == "render_video":
        from .render import render_video

        return render_video
    raise AttributeError(name)
