"""``gaitshift robot check``: what will fail on a robot, found before any simulation.

Checks, each a :class:`Finding` (one line; ``ok`` False is a problem):

* **sole frame** (:mod:`gaitshift.robots.statics`): in the standing pose each sole's normal is vertical
  within :data:`~gaitshift.robots.statics.LEVEL_TOL` and its x axis points forward (within 45°);
* **balance**: the CoM's ground projection is inside the support polygon of the two soles;
* **static torque**: the least joint torques that hold the standing pose against gravity, as a fraction
  of the model's torque limits (> 1: the robot cannot stand);
* **standing limits**: a joint within :data:`STANDING_LIMIT_TOL` of its range limit in the standing pose
  (given in the YAML or left at qpos0) is a problem: it has no room to move one way;
* with a scenario, **reach and joint limits**: the whole-body IK (:mod:`gaitshift.wholebody.ik`) follows
  the plan at :data:`~gaitshift.wholebody.checks.CHECK_RATE` Hz within its tolerances (a foot out of
  reach, a straight knee or a joint held at its limit is reported with the time and the joint);
* with a scenario, **joint speeds**: peak |q̇| of every joint against its limit (``RobotConfig.velocity_limit``:
  the YAML's ``velocity_limits``, and the model's torque limit / joint damping, the speed above which the
  motor alone cannot drive the joint: ``RobotConfig.speed_limits``); joints without a limit are counted,
  not failed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from gaitshift.robots.config import RobotConfig
from gaitshift.robots.statics import LEVEL_TOL, standing_statics
from gaitshift.trajectory.contract import Trajectory

#: largest angle between a sole's x axis and the base's x axis in the standing pose, rad
HEADING_TOL = math.radians(45.0)
#: a joint this close to its range limit in the standing pose (rad) is at the limit
STANDING_LIMIT_TOL = 0.01


@dataclass(frozen=True)
class Finding:
    """One line of the report: ``check`` name, ``ok`` (False: a problem) and the ``text``."""

    check: str
    ok: bool
    text: str

    def line(self) -> str:
        return f"{'ok     ' if self.ok else 'PROBLEM'} {self.check}: {self.text}"


def _sole_findings(robot: RobotConfig) -> list[Finding]:
    st = standing_statics(robot)
    out = []
    for i, side in enumerate(("left", "right")):
        body = robot.sole_bodies[i]
        tilt, heading = float(st.tilt[i]), float(st.heading[i])
        ok = tilt <= LEVEL_TOL and abs(heading) <= HEADING_TOL
        text = (
            f"{side} sole ({body}) normal {math.degrees(tilt):.1f} deg from vertical, x axis "
            f"{math.degrees(heading):.1f} deg from forward in the standing pose"
        )
        if not ok:
            text += " (set sole_orientation: geoms, or a quaternion per side, in the robot YAML)"
        out.append(Finding("sole frame", ok, text))
    out.append(_balance_finding(st.com_margin, st.support_area))
    j = int(np.argmax(st.torque_fraction))
    frac = float(st.torque_fraction[j])
    out.append(
        Finding(
            "static torque",
            frac <= 1.0,
            f"standing needs {frac:.2f} of the torque limit at {robot.joint_names[j]} "
            f"({abs(st.torque[j]):.1f} of {robot.torque_limit[j]:.1f} N m)",
        )
    )
    return out


def _standing_limit_findings(robot: RobotConfig) -> list[Finding]:
    """A PROBLEM per joint at its range limit in the standing pose, else the closest approach (ok)."""
    model = robot.model()
    qadr = np.array([model.jnt_qposadr[model.joint(n).id] for n in robot.joint_names])
    q = robot.standing_qpos(model)[qadr]
    lo, hi = robot.joint_range[:, 0], robot.joint_range[:, 1]
    gap = np.minimum(q - lo, hi - q)

    def text(j: int) -> str:
        return f"{robot.joint_names[j]} = {q[j]:.3f} rad, range [{lo[j]:.3f}, {hi[j]:.3f}] rad"

    out = [
        Finding("standing limits", False, f"{text(j)}: at its range limit in the standing pose")
        for j in (int(i) for i in np.flatnonzero(gap <= STANDING_LIMIT_TOL))
    ]
    if out or not np.any(np.isfinite(gap)):
        return out
    j = int(np.argmin(gap))
    return [Finding("standing limits", True, f"closest approach {gap[j]:.3f} rad ({text(j)})")]


def _balance_finding(margin: float, area: bool) -> Finding:
    """The CoM's ground projection against the support polygon (``margin`` m, > 0 inside)."""
    if not area:
        return Finding(
            "balance",
            False,
            f"the soles' contact points lie on a line in the standing pose: no support polygon (CoM "
            f"{abs(margin) * 1e3:.1f} mm from it; check sole_orientation in the robot YAML)",
        )
    return Finding(
        "balance",
        margin > 0,
        f"CoM {abs(margin) * 1e3:.1f} mm {'inside' if margin > 0 else 'OUTSIDE'} the support "
        "polygon of the soles in the standing pose",
    )


def _plan_findings(robot: RobotConfig, traj: Trajectory) -> list[Finding]:
    from gaitshift.wholebody.checks import CHECK_RATE
    from gaitshift.wholebody.ik import IKInfeasibleError, IKSettings, WholeBodyIK

    k = max(1, round(1.0 / (CHECK_RATE * traj.dt)))
    try:
        joints = WholeBodyIK(robot, IKSettings()).solve(traj, 1.0 / (k * traj.dt), check_velocities=False)
    except IKInfeasibleError as exc:
        check = "joint limits" if exc.cause.startswith("joint limit") else "reach"
        return [Finding(check, False, str(exc))]
    ik = joints.meta["ik"]
    out = [
        Finding(
            "reach",
            True,
            f"IK follows the plan: CoM error {ik['max_com_error_m'] * 1e3:.2f} mm, soles "
            f"{ik['max_sole_position_error_m'] * 1e3:.2f} mm"
            + "".join(f"; dropped {t}" for t in ik.get("dropped_tasks", [])),
        ),
        _limit_finding(robot, joints.qpos),
    ]
    model = robot.model()
    vadr = np.array([model.jnt_dofadr[model.joint(n).id] for n in robot.joint_names])
    return out + _speed_findings(robot, np.max(np.abs(joints.qvel[:, vadr]), axis=0))


def _limit_finding(robot: RobotConfig, qpos: np.ndarray) -> Finding:
    """Smallest distance of any joint to its range along the IK motion (the IK keeps them inside)."""
    model = robot.model()
    qadr = np.array([model.jnt_qposadr[model.joint(n).id] for n in robot.joint_names])
    q = qpos[:, qadr]
    gap = np.minimum(q - robot.joint_range[:, 0], robot.joint_range[:, 1] - q).min(axis=0)
    if not np.any(np.isfinite(gap)):
        return Finding("joint limits", True, "the model gives no joint ranges")
    j = int(np.argmin(gap))
    return Finding(
        "joint limits",
        True,
        f"closest approach {gap[j]:.3f} rad ({robot.joint_names[j]}, range "
        f"[{robot.joint_range[j, 0]:.3f}, {robot.joint_range[j, 1]:.3f}] rad)",
    )


def _speed_findings(robot: RobotConfig, peak: np.ndarray) -> list[Finding]:
    lim, source = robot.speed_limits()
    known = np.isfinite(lim)
    out = [
        Finding(
            "joint speed",
            False,
            f"{robot.joint_names[j]} needs {peak[j]:.2f} rad/s, above its limit {lim[j]:.2f} rad/s ({source[j]})",
        )
        for j in (int(i) for i in np.flatnonzero(known & (peak > lim)))
    ]
    if np.any(known) and not out:
        ratio = np.where(known, peak / np.where(known, lim, 1.0), 0.0)
        j = int(np.argmax(ratio))
        out.append(
            Finding(
                "joint speed",
                True,
                f"peak {ratio[j]:.2f} of the limit ({robot.joint_names[j]}: {peak[j]:.2f} of {lim[j]:.2f} rad/s)",
            )
        )
    if not np.all(known):
        j = int(np.argmax(np.where(known, -np.inf, peak)))
        out.append(
            Finding(
                "joint speed",
                True,
                f"{int(np.sum(~known))} joints have no velocity_limits entry (unchecked); fastest "
                f"{robot.joint_names[j]} {peak[j]:.2f} rad/s",
            )
        )
    return out


def robot_check(robot: RobotConfig, traj: Trajectory | None = None) -> list[Finding]:
    """Every finding for ``robot`` (standing pose) and, given a plan ``traj``, for its motion."""
    out = _sole_findings(robot) + _standing_limit_findings(robot)
    if traj is not None:
        out += _plan_findings(robot, traj)
    return out


def check_plan_for(scenario: Any, robot_name: str | None) -> tuple[RobotConfig, Trajectory]:
    """The robot and the plan that ``gaitshift simulate SCENARIO --robot R`` would run."""
    from gaitshift.api import plan, with_robot
    from gaitshift.robots import load_robot
    from gaitshift.scenario import load_scenario

    sc, name = with_robot(load_scenario(scenario), robot_name)
    return load_robot(name), plan(sc)
