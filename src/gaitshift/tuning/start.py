"""A new robot's gait keys derived from its model: where ``gaitshift robot tune`` starts its search.

**Flight.** A running stance must reverse the touchdown speed ``g T_f / 2`` of the flight before it
(``T_f`` the flight time): the mean vertical force over a stance of ``T_s`` is ``m g (1 + T_f / T_s)``
and, for a force that rises and falls like a half sine, its peak is ``pi / 2`` of the mean's excess,

.. math::

    \\frac{F_{peak}}{m g} = 1 + \\frac{\\pi}{2} \\frac{T_f}{T_s} \\le n,
    \\qquad n = \\frac{\\tau_{knee,max}}{\\tau_{knee}(m g)}                                     (1)

with ``tau_knee(m g)`` the knee torque that holds the whole weight on one sole in the standing pose
(``J^T (0, 0, m g)`` at the sole site) and ``tau_knee,max`` the knee's torque limit: the knee is the
joint that carries a bent leg's load. So ``T_f <= (n - 1) (2 / pi) T_s``, and the flight scale is that
over the nominal flight, at most 1. Measured on the shipped robots: G1 n = 3.90 (scale 1, shipped 1),
T1 n = 1.42 (0.44; shipped 0.5, found by bisection), H1 3.43 (1, shipped 1); Berkeley 2.40 and OP3
1.89 give 1 and 0.94 where bisection found 0.25: their limits lie elsewhere (ankle stops, servo speed),
which the search finds.

**Turning.** The stance leg's hip yaw joint turns with the body: at a yaw rate ``w`` it moves at
``w / |a_z|`` (``a_z`` the vertical part of its axis in the standing pose), and the swing leg's turns
as much again to set the next foot on the new heading, so

.. math::

    w_{max} = \\frac{|a_z|\\, \\dot q_{yaw,max}}{2}                                             (2)

with ``qdot_yaw,max`` the yaw joint's speed limit (the robot YAML's ``velocity_limits`` or the
MJCF's torque limit / joint damping: Apollo's hip yaw 0.70 rad/s). The yaw joint of a leg is its joint
whose axis is most vertical in the standing pose. No cap when the speed limit is unknown.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from gaitshift.planners.locomotion.params import PAPER_HEIGHT, PAPER_TIMING
from gaitshift.robots.config import RobotConfig

__all__ = ["StartingGait", "starting_gait"]


@dataclass(frozen=True)
class StartingGait:
    """The model-derived start of the search (module docstring).

    Attributes:
        flight_scale: eq. (1), in (0, 1]. knee_ratio: n of eq. (1).
        max_yaw_rate: eq. (2), rad/s; None: no cap (no speed limit known).
        yaw_joints: the (left, right) yaw joints eq. (2) read.
    """

    flight_scale: float
    knee_ratio: float
    max_yaw_rate: float | None
    yaw_joints: tuple[str, str]


def starting_gait(robot: RobotConfig) -> StartingGait:
    """The starting gait keys of ``robot`` (module docstring)."""
    m = robot.model()
    d = mujoco.MjData(m)
    d.qpos[:] = robot.standing_qpos(m)
    mujoco.mj_forward(m, d)
    n = _knee_ratio(robot, m, d)
    tau = math.sqrt(robot.com_height / PAPER_HEIGHT)  # the locomotion planner's Froude-scaled timing
    single, flight = PAPER_TIMING["run_single"] * tau, PAPER_TIMING["flight"] * tau
    t_max = max(0.0, (n - 1.0) * (2.0 / math.pi) * single)
    scale = min(1.0, t_max / flight)
    yaws = _yaw_joints(robot, m, d)
    limits, _ = robot.speed_limits()
    rates = [abs(float(d.xaxis[m.joint(j).id][2])) * limits[robot.joint_names.index(j)] / 2.0 for j in yaws]
    rate = min(rates)
    return StartingGait(
        flight_scale=max(scale, 0.05),  # a flight of some milliseconds still: the search goes lower if needed
        knee_ratio=n,
        max_yaw_rate=float(rate) if math.isfinite(rate) else None,
        yaw_joints=yaws,
    )


def _knee_ratio(robot: RobotConfig, m: mujoco.MjModel, d: mujoco.MjData) -> float:
    """n of eq. (1): the smaller over the two legs."""
    weight = np.array([0.0, 0.0, robot.mass * float(-m.opt.gravity[2])])
    out = []
    for site, knee in zip(robot.SOLE_SITES, robot.knees, strict=True):
        jac = np.zeros((3, m.nv))
        mujoco.mj_jacSite(m, d, jac, None, m.site(site).id)
        load = abs(float((jac.T @ weight)[m.jnt_dofadr[m.joint(knee).id]]))
        limit = float(robot.torque_limit[robot.joint_names.index(knee)])
        out.append(limit / load if load > 0 else math.inf)
    return min(out)


def _yaw_joints(robot: RobotConfig, m: mujoco.MjModel, d: mujoco.MjData) -> tuple[str, str]:
    """Per leg, the leg joint whose axis is most vertical in the standing pose."""
    legs = [robot.leg_joints[: len(robot.leg_joints) // 2], robot.leg_joints[len(robot.leg_joints) // 2 :]]
    left, right = (max(leg, key=lambda j: abs(float(d.xaxis[m.joint(j).id][2]))) for leg in legs)
    return left, right
