"""Simulate a scenario: the one path the CLI, campaigns, teleop, the web view and the benchmarks take.

.. code-block:: text

    scenario (name, YAML path or loaded) + robot
      -> driver (control.drivers: re-plans a streaming plan) or the offline plan
      -> options: SimOptions defaults < the scenario's ``sim:`` block < the caller's options
      -> pushes: the caller's replace the scenario's; a bare impulse J (N s) becomes the lateral pushes
         at mid-stance of steps 4 and 8 of the plan (gaitshift.sim.pushes.mid_stance_pushes)
      -> gaitshift.sim.loop.simulate -> ScenarioRun (the scenario, robot, driver, final plan, result)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.control.drivers import PlanDriver, prepare
from gaitshift.errors import check_choice
from gaitshift.robots.config import RobotConfig
from gaitshift.scenario.terrain import world_ground
from gaitshift.sim.bumps import Bump
from gaitshift.sim.loop import SimOptions, TickHook, simulate
from gaitshift.sim.pushes import Push, mid_stance_pushes
from gaitshift.sim.result import SimResult
from gaitshift.trajectory.contract import Trajectory

__all__ = ["ScenarioRun", "options_of", "run_prepared", "scenario_options", "simulate_scenario"]


@dataclass(frozen=True)
class ScenarioRun:
    """One simulated scenario.

    Attributes:
        scenario: the loaded scenario (its robot written in); robot: the robot config it ran on.
        driver: the plan driver (None: the plan executed as planned); plan: the plan at start.
        result: the run (log, metrics, fall).
    """

    scenario: Any
    robot: RobotConfig
    driver: PlanDriver | None
    plan: Trajectory
    result: SimResult

    @property
    def trajectory(self) -> Trajectory:
        """The run's plan as the loop tracked it (:attr:`SimResult.plan`: with a driver, its windows joined);
        the plan itself for a result that carries none."""
        return self.result.plan if self.result.plan is not None else self.plan


def scenario_options(scenario: Any) -> dict[str, Any]:
    """The scenario's ``sim:`` keys as :class:`SimOptions` fields (``pushes`` and ``bumps`` as
    :class:`~gaitshift.sim.pushes.Push` and :class:`~gaitshift.sim.bumps.Bump` tuples)."""
    sim = getattr(scenario, "sim", None)
    out = dict(sim.given()) if sim is not None else {}
    if "pushes" in out:
        out["pushes"] = tuple(
            Push(
                t=p["t"],
                impulse=float(np.linalg.norm(p["impulse"])),
                duration=p["duration"],
                direction=tuple(p["impulse"]),
            )
            for p in out["pushes"]
        )
    if "bumps" in out:
        out["bumps"] = tuple(Bump(**b) for b in out["bumps"])
    return out


def options_of(plan: Trajectory, base: dict[str, Any], given: dict[str, Any]) -> SimOptions:
    """:class:`SimOptions` from the scenario's keys ``base`` overridden by ``given`` (None values
    ignored); given ``pushes`` replace the scenario's, each a :class:`Push` or an impulse J N s (the
    lateral pushes at mid-stance of steps 4 and 8 of ``plan``). An unknown key is an :class:`InputError`."""
    names = {f.name for f in fields(SimOptions)}
    given = {k: v for k, v in given.items() if v is not None}
    for key in given:
        check_choice("options", key, sorted(names))
    if "pushes" in given:
        pushes: list[Push] = []
        for p in given["pushes"]:
            pushes.extend([p] if isinstance(p, Push) else mid_stance_pushes(plan, p) if p > 0 else [])
        given["pushes"] = tuple(pushes)
    return SimOptions(**(base | given))


def run_prepared(
    prepared: tuple[Any, RobotConfig, PlanDriver | None, Trajectory], hooks: Sequence[TickHook] = (), **options: Any
) -> ScenarioRun:
    """Simulate what :func:`gaitshift.control.drivers.prepare` returned, with ``options``
    (:func:`simulate_scenario`)."""
    sc, cfg, drv, plan = prepared
    opts = options_of(plan, scenario_options(sc), options)
    result = simulate(plan, opts, driver=drv, hooks=hooks, robot=cfg, ground=world_ground(sc))  # known or not
    return ScenarioRun(sc, cfg, drv, plan, result)


def simulate_scenario(
    scenario: Any,
    robot: str | Path | RobotConfig | None = None,
    *,
    driver: PlanDriver | None = None,
    hooks: Sequence[TickHook] = (),
    **options: Any,
) -> ScenarioRun:
    """Simulate ``scenario`` (a built-in name, a YAML path or a loaded scenario) on ``robot`` (default:
    the scenario's, else g1) closed loop (module docstring). ``options`` are :class:`SimOptions` fields
    (None: the scenario's or the default); ``driver`` replaces the scenario's driver (a live session's);
    ``hooks`` are called after every tick (:func:`gaitshift.sim.loop.simulate`); ``terrain`` says what
    the planner is told of the scenario's terrain (:func:`gaitshift.control.drivers.prepare`)."""
    terrain = options.pop("terrain", None)
    sc, cfg, own, plan = prepare(scenario, robot, options.get("control_period") or 0.002, terrain)
    drv = driver if driver is not None else own
    return run_prepared((sc, cfg, drv, drv.trajectory if drv is not None else plan), hooks, **options)
