"""Scale a ``planner: locomotion`` scenario (a live-command script) to a robot.

A locomotion scenario sets few numbers: the keys it leaves out take their defaults from the facts of
the robot it names (:func:`gaitshift.planners.locomotion.params.params_from_scenario`: CoM height, leg
length, soles, foot separation, paper 001's timings Froude-scaled to it). Scaling it to another robot
therefore leaves those keys out again (they default from the new robot) and writes, for the keys that
are set, the numbers of the rule of :mod:`gaitshift.wholebody.scaling` with lambda = h' / h (h: the
CoM height the scenario resolves to on its own robot, h': the new robot's):

* robot facts (``height``, ``leg_length``, ``foot.size``, ``step_width``) become the new robot's;
* lengths x lambda: ``swing_height``, ``foot.zmp_margin``, ``limits.max_stride``, ``limits.width``,
  the goal positions of ``goto`` commands;
* durations x tau (tau = 1 with ``time_scale="keep"``, sqrt(lambda) with ``"froude"``): ``timing.*``,
  the command times, ``stop_at``;
* speeds x lambda / tau: the commanded vx, vy, ``switch.*``, ``limits.max_speed`` and the vx, vy parts
  of ``limits.max_accel``; angles and yaw rates are kept.

Then the robot YAML's ``gait`` choices (rule 5), on the numbers the scaled scenario resolves to on the
new robot (so they apply to defaulted keys too, which are then written): ``flight_scale`` x the flight,
``step_width``, ``step_time_scale`` x the walking and running single supports, the double support and
the stride limit, ``max_stride`` caps the stride limit, ``swing_height``, ``max_yaw_rate`` caps the
turn rate.
"""

from __future__ import annotations

from typing import Any

from gaitshift.planners.locomotion.params import LocomotionParams, params_from_scenario
from gaitshift.robots.config import RobotConfig
from gaitshift.scenario.facts import RobotFacts
from gaitshift.scenario.locomotion import LocomotionScenario, LocomotionTiming

#: dotted keys x lambda (lengths)
LENGTH_KEYS = ("swing_height", "foot.zmp_margin", "limits.max_stride", "limits.width")
#: dotted keys x lambda / tau (speeds)
SPEED_KEYS = ("switch.walk_to_run", "switch.run_to_walk", "limits.max_speed")
#: dotted keys x tau (durations)
TIME_KEYS = (*(f"timing.{k}" for k in LocomotionTiming.model_fields), "stop_at")


def locomotion_height(scenario: Any, facts: RobotFacts | None) -> float:
    """The CoM height (m) a locomotion scenario resolves to on the robot of ``facts`` (None: paper 001's)."""
    return params_from_scenario(scenario, facts).height


def _scaled(data: dict[str, Any], dotted: str, factor: float) -> None:
    """``data[dotted]`` x ``factor`` when it is set (a number or a list of numbers)."""
    *parents, leaf = dotted.split(".")
    node: Any = data
    for p in parents:
        node = node.get(p) if isinstance(node, dict) else None
    if not isinstance(node, dict) or node.get(leaf) is None:
        return
    v = node[leaf]
    node[leaf] = [x * factor for x in v] if isinstance(v, list | tuple) else v * factor


def scale_locomotion_data(data: dict[str, Any], robot: RobotConfig, lam: float, tau: float) -> None:
    """Scale the dumped locomotion scenario ``data`` in place (module docstring)."""
    for key, fact in (("height", robot.com_height), ("leg_length", robot.leg_length)):
        if data.get(key) is not None:
            data[key] = fact
    if data["foot"].get("size") is not None:
        data["foot"]["size"] = list(robot.sole_size)
    if data.get("step_width") is not None:
        data["step_width"] = robot.foot_separation
    for key in LENGTH_KEYS:
        _scaled(data, key, lam)
    for key in SPEED_KEYS:
        _scaled(data, key, lam / tau)
    for key in TIME_KEYS:
        _scaled(data, key, tau)
    accel = data["limits"].get("max_accel")
    if accel is not None:
        data["limits"]["max_accel"] = [accel[0] * lam / tau, accel[1] * lam / tau, accel[2]]
    data["commands"] = [_command(c, lam, tau) for c in data["commands"]]
    _apply_gait(data, robot)


def _command(c: dict[str, Any], lam: float, tau: float) -> dict[str, Any]:
    out = dict(c, t=c["t"] * tau, vx=c["vx"] * lam / tau, vy=c["vy"] * lam / tau)
    if c.get("goto") is not None:
        out["goto"] = dict(c["goto"], x=c["goto"]["x"] * lam, y=c["goto"]["y"] * lam)
    return out


def _resolved(data: dict[str, Any], robot: RobotConfig) -> LocomotionParams:
    return params_from_scenario(LocomotionScenario.model_validate(data), robot.facts())


def _apply_gait(data: dict[str, Any], robot: RobotConfig) -> None:
    """The robot YAML's ``gait`` choices on the numbers ``data`` resolves to on ``robot``."""
    p = _resolved(data, robot)
    timing, limits = data["timing"], data["limits"]
    if robot.flight_scale != 1.0:
        timing["flight"] = p.timing.flight * robot.flight_scale
    if robot.step_width is not None:
        data["step_width"] = robot.step_width
    s = robot.step_time_scale
    if s != 1.0:
        for key in ("walk_single", "run_single", "double"):
            timing[key] = getattr(p.timing, key) * s
        limits["max_stride"] = p.limits.max_stride * s
    if robot.max_stride is not None:
        limits["max_stride"] = min(limits.get("max_stride") or p.limits.max_stride, robot.max_stride)
    if robot.swing_height is not None:
        data["swing_height"] = robot.swing_height
    if robot.max_yaw_rate is not None:
        limits["max_yaw_rate"] = min(limits.get("max_yaw_rate") or p.limits.max_yaw_rate, robot.max_yaw_rate)
