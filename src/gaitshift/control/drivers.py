"""Plan drivers: what re-plans a streaming plan from the measured state during a closed-loop run.

A driver has ``trajectory`` (the plan as known now), ``replans`` (how many re-plans were made),
``duration_bound`` (an upper bound of the plan time, s), ``step_feedback`` (whether the loop's
capture-point step feedback stays on) and ``maybe_replan(t, com, com_vel)`` (called every tick;
returns the new plan when it re-planned or extended). :data:`DRIVERS` maps a scenario's planner to
the driver that runs it; a planner without one (``tvlip``) is executed as planned, with the
capture-point step feedback of :mod:`gaitshift.control.feedback`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

import numpy as np

from gaitshift.scenario.facts import RobotFacts
from gaitshift.trajectory.contract import Trajectory

__all__ = ["DRIVERS", "PlanDriver", "driver_for", "prepare"]


class PlanDriver(Protocol):
    """The interface the loop drives (module docstring)."""

    trajectory: Trajectory
    replans: int
    duration_bound: float
    step_feedback: bool

    def maybe_replan(self, t: float, com: np.ndarray, com_vel: np.ndarray) -> Trajectory | None: ...


def _vhip(sc: Any, _facts: RobotFacts | None, _control_period: float) -> PlanDriver:
    """The VHIP generator's driver (its own sample step and robot-free scenario)."""
    from gaitshift.control.vhip_driver import VhipDriver

    return VhipDriver(sc)


def _locomotion(sc: Any, facts: RobotFacts | None, control_period: float) -> PlanDriver:
    from gaitshift.control.locomotion_driver import LocomotionDriver

    return LocomotionDriver(sc, facts, control_period)


#: planner -> driver factory (scenario, robot facts, control period)
DRIVERS: dict[str, Callable[[Any, RobotFacts | None, float], PlanDriver]] = {"vhip": _vhip, "locomotion": _locomotion}


def driver_for(sc: Any, facts: RobotFacts | None, control_period: float) -> PlanDriver | None:
    """The driver of the scenario's planner, or None for a plan executed as planned."""
    make = DRIVERS.get(sc.planner)
    return None if make is None else make(sc, facts, control_period)


def prepare(
    scenario: Any, robot: Any = None, control_period: float = 0.002, terrain: str | None = None
) -> tuple[Any, Any, PlanDriver | None, Trajectory]:
    """A scenario on a robot, ready to run: the scenario (a built-in name, a YAML path or a loaded one;
    its robot written in), the robot config (``robot``: a name, a robot YAML path or a
    :class:`gaitshift.robots.RobotConfig`; None: the scenario's, else g1), the driver of its planner
    (:func:`driver_for`) and the plan as known at the start. What a controller is built from and a
    simulation runs (:meth:`gaitshift.control.controller.Controller.from_scenario`,
    :func:`gaitshift.sim.scenario_run.simulate_scenario`).

    ``terrain`` says what the planner is told of the scenario's ``terrain:``
    (:data:`gaitshift.scenario.sim_settings.TERRAIN_KNOWLEDGE`; None: the scenario's ``sim: terrain``,
    else ``known``): ``blind`` plans on flat ground at the height the robot starts on (a blind robot
    still knows where it stands); ``perceived`` starts on the blind plan and moves its footholds onto
    the controller's elevation map (:class:`~gaitshift.control.perceived_driver.PerceivedDriver`). The
    scenario returned keeps its terrain: the world is built on it whatever the planner knows.

    Raises:
        InputError: an unknown ``terrain``; ``known`` terrain for a live-command scenario (its
            generator plans on flat ground); ``perceived`` for a planner other than ``tvlip``.
    """
    from gaitshift.api import plan, robot_facts, with_robot
    from gaitshift.robots.config import RobotConfig, load_robot
    from gaitshift.scenario import load_scenario

    sc = load_scenario(scenario)  # a name, a path, a dict or a loaded scenario; anything else is refused
    given = robot if isinstance(robot, RobotConfig) else None
    sc, robot_name = with_robot(sc, None if given is not None else (None if robot is None else str(robot)))
    cfg = given if given is not None else load_robot(robot_name)
    planned, knowledge = _planned(sc, terrain)
    if knowledge == "perceived":  # the blind plan, its footholds moved onto the map as it grows
        from gaitshift.control.perceived_driver import PerceivedDriver, PerceivedSettings

        sim = getattr(sc, "sim", None)
        said = {k: getattr(sim, k, None) for k in ("replan_lead", "footholds")}  # the rest: the defaults
        settings = PerceivedSettings(**{k: v for k, v in said.items() if v is not None})
        perceived = PerceivedDriver(planned, plan(planned), settings)
        return sc, cfg, perceived, perceived.trajectory
    driver = driver_for(planned, robot_facts(planned), control_period)
    return sc, cfg, driver, driver.trajectory if driver is not None else plan(planned)


#: half the length, m, of the flat ground a blind planner assumes around the start
BLIND_REACH = 1000.0


def _flat_where_it_stands(pieces: Any) -> tuple[Any, ...]:
    """The terrain a blind planner assumes: flat at the height of the scenario's ground at x = 0 (the
    plans' start), as one piece (none when that height is the floor's)."""
    from gaitshift.scenario.terrain import TerrainPiece, terrain_of

    z0 = float(terrain_of(pieces).height(0.0))
    return (TerrainPiece(x=(-BLIND_REACH, BLIND_REACH), z=(z0, z0)),) if z0 > 0 else ()


def _planned(sc: Any, terrain: str | None) -> tuple[Any, str]:
    """The scenario the planner plans (:func:`prepare`): ``sc`` itself, or without its terrain (blind,
    perceived); and what the planner is told."""
    from gaitshift.errors import InputError, check_choice
    from gaitshift.scenario.sim_settings import TERRAIN_KNOWLEDGE

    sim = getattr(sc, "sim", None)
    knowledge = terrain or (sim.terrain if sim is not None else None) or "known"
    field = "--terrain" if terrain is not None else "sim.terrain"
    check_choice(field, knowledge, TERRAIN_KNOWLEDGE)
    if knowledge == "perceived" and sc.planner != "tvlip":
        raise InputError(field, knowledge, f"known or blind for a {sc.planner} scenario (perceived: tvlip only)")
    if not getattr(sc, "terrain", ()):
        return sc, "known"
    if knowledge == "known" and any(p.blocks is not None for p in sc.terrain):
        raise InputError(field, knowledge, "blind or perceived on a field of blocks (a 2-D ground: planners take z(x))")
    if knowledge in ("blind", "perceived"):
        return sc.model_copy(update={"terrain": _flat_where_it_stands(sc.terrain)}), knowledge
    if sc.planner == "locomotion":
        raise InputError(
            field, knowledge, "blind for a live-command scenario on terrain (its generator plans on flat ground)"
        )
    return sc, knowledge
