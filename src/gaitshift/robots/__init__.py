"""Robots: configs (YAML) of real humanoid models, loaded offline, with the facts read from the MJCF.

Public API::

    from gaitshift.robots import load_robot
    g1 = load_robot("g1")      # RobotConfig: MJCF path, soles, limits, mass, CoM height, leg length
"""

from gaitshift.robots.config import RobotConfig, builtin_robots, load_robot

__all__ = ["RobotConfig", "builtin_robots", "load_robot"]
