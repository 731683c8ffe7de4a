"""The top-level planning call: a scenario (object, built-in name or YAML path) -> Trajectory.

It resolves the scenario's robot, if it names one (``robot: g1``), into the few numbers its defaults
come from (:meth:`gaitshift.robots.config.RobotConfig.facts`), so that planners get plain numbers and
never load a model, then calls the planner the scenario names (:mod:`gaitshift.planners.registry`).
"""

from __future__ import annotations

import inspect
from typing import Any

from gaitshift.errors import InputError
from gaitshift.planners.registry import planner_for
from gaitshift.scenario.loader import load_scenario
from gaitshift.trajectory.contract import Trajectory

__all__ = ["named_robot", "plan", "plan_robot", "robot_facts", "with_robot"]


def robot_facts(scenario: Any) -> Any:
    """The :class:`~gaitshift.scenario.facts.RobotFacts` of the scenario's robot, or None."""
    name = getattr(scenario, "robot", None)
    if name is None:
        return None
    from gaitshift.robots.config import load_robot

    return load_robot(name).facts()


def with_robot(scenario: Any, robot: str | None) -> tuple[Any, str]:
    """The scenario and the robot it runs on, from its ``robot`` key and a ``--robot`` choice.

    * no ``--robot``: the scenario's robot, else ``g1``;
    * ``--robot`` and a scenario without a robot: ``--robot``, written into the scenario (so that a
      locomotion plan takes its defaults from that robot);
    * both, naming the same robot: that robot; naming different robots: an error, because a scenario
      made for one robot (its CoM height, strides, soles) is not a plan for another. Scale it first:
      ``gaitshift scale SCENARIO --robot R --out r.yaml``.

    Raises:
        InputError: the two robots differ, or either does not load.
    """
    own = getattr(scenario, "robot", None)
    if robot is not None and own is None and "robot" in type(scenario).model_fields:
        scenario = scenario.model_copy(update={"robot": robot})
    return scenario, _one_robot(own, robot, scenario.name)


def named_robot(meta: dict[str, Any]) -> str | None:
    """The robot a plan's ``meta`` names: ``meta.robot`` (the locomotion planner writes it) or the
    ``robot`` of ``meta.scenario`` (the scenario the others write), or None."""
    own = meta.get("robot")
    if isinstance(own, str) and own:
        return own
    scenario = meta.get("scenario")
    name = scenario.get("robot") if isinstance(scenario, dict) else None
    return None if name is None else str(name)


def plan_robot(traj: Trajectory, robot: str | None) -> str:
    """The robot a plan is for, from the ``robot`` of the scenario it was planned from (``traj.meta``)
    and a ``--robot`` choice, by the rules of :func:`with_robot` (no robot anywhere: ``g1``).

    Raises:
        InputError: the two robots differ, or either does not load.
    """
    scenario = traj.meta.get("scenario")
    name = scenario.get("name", "the plan") if isinstance(scenario, dict) else scenario or "the plan"
    return _one_robot(named_robot(traj.meta), robot, str(name))


def _one_robot(own: str | None, robot: str | None, scenario: str) -> str:
    """``robot`` if given and the same robot as the scenario's own ``own``; else ``own``, else g1."""
    from gaitshift.robots.config import load_robot

    if robot is None:
        return own or "g1"
    if own is not None and load_robot(own) != load_robot(robot):
        raise InputError(
            "--robot",
            robot,
            f"the scenario's robot {own!r} (scenario {scenario} is made for {own}; scale it first: "
            f"gaitshift scale {scenario} --robot {robot} --out {load_robot(robot).name}.yaml)",
        )
    return robot


def plan(scenario: Any) -> Trajectory:
    """Plan a scenario (object, built-in name or YAML path) with the planner it names; planners that
    take robot facts get those of the scenario's robot."""
    if not hasattr(scenario, "planner"):
        scenario = load_scenario(scenario)
    fn = planner_for(scenario.planner)
    facts = robot_facts(scenario)
    if facts is None or len(inspect.signature(fn).parameters) < 2:
        return fn(scenario)
    return fn(scenario, facts)  # type: ignore[call-arg]
