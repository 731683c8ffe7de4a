"""Plan a locomotion scenario: its scripted commands fed to the generator, stop, end at rest."""

from __future__ import annotations

from typing import Any

from gaitshift.planners.locomotion.generator import LocomotionGenerator
from gaitshift.planners.locomotion.params import params_from_scenario
from gaitshift.planners.streaming.script import CommandScript
from gaitshift.scenario.facts import RobotFacts
from gaitshift.trajectory.contract import Trajectory

__all__ = ["apply", "plan_scenario", "script_of", "stop_time"]

#: time allowed after the stop request for the ramp-down and the closing step, s
STOP_BUDGET = 60.0


def stop_time(sc: Any) -> float:
    """When the stop is requested: ``stop_at``, or 3 s after the last command."""
    return float(sc.stop_at) if sc.stop_at is not None else max(c.t for c in sc.commands) + 3.0


def apply(gen: LocomotionGenerator, cmd: Any) -> None:
    """Apply one scripted command (a velocity or a goto) of a locomotion scenario."""
    if cmd.goto is not None:
        gen.goto(cmd.goto.x, cmd.goto.y, cmd.goto.yaw)
    else:
        gen.command(cmd.vx, cmd.vy, cmd.yaw_rate)


def script_of(sc: Any) -> CommandScript:
    """The scenario's commands and stop time as a :class:`CommandScript`."""
    return CommandScript([(c.t, c) for c in sc.commands], stop_time(sc), apply)


def plan_scenario(sc: Any, facts: RobotFacts | None = None) -> Trajectory:
    """Plan a ``planner: locomotion`` scenario (with the facts of its robot, if it names one)."""
    gen = LocomotionGenerator(params_from_scenario(sc, facts))
    script = script_of(sc)
    script.run(gen, max_time=script.stop_at + STOP_BUDGET)
    traj = gen.trajectory()
    traj.meta["scenario"] = sc.name
    if facts is not None:
        traj.meta["robot"] = facts.name
    return traj
