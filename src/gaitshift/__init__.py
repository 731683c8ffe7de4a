"""gaitshift: walking, running and walk-run transitions for biped robots.

Public API::

    import gaitshift
    sc = gaitshift.load_scenario("paper001-table2-walk-run-walk")
    traj = gaitshift.plan(sc)            # -> Trajectory (file contract of gaitshift.trajectory)
    traj.save("plan.npz")
    k = gaitshift.stiffness(0.95, 0.4, 0.15, 0.15)   # T_w, T_r, v_r, T_t0, T_t1

    ctrl = gaitshift.Controller.from_scenario("g1-walk")      # the robot's brain: SensorFrame -> MotorCommand
    run = gaitshift.simulate("g1-walk")                       # the brain in the simulated world

The planning names load numpy only; ``Controller``, ``SensorFrame``, ``MotorCommand`` and ``simulate``
load MuJoCo on first use.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from gaitshift.api import plan
from gaitshift.errors import GaitshiftError, InfeasibleError, InputError, ScenarioError, StiffnessError
from gaitshift.models.stiffness import Stiffness, stiffness
from gaitshift.planners.locomotion.generator import LocomotionGenerator
from gaitshift.planners.tvlip.replanner import Replanner
from gaitshift.scenario import builtin_names, load_scenario
from gaitshift.trajectory.contract import Trajectory

if TYPE_CHECKING:
    from gaitshift.control.controller import Controller
    from gaitshift.control.frames import MotorCommand, SensorFrame
    from gaitshift.sim.scenario_run import simulate_scenario as simulate

__all__ = [
    "Controller",
    "GaitshiftError",
    "InfeasibleError",
    "InputError",
    "LocomotionGenerator",
    "MotorCommand",
    "Replanner",
    "ScenarioError",
    "SensorFrame",
    "Stiffness",
    "StiffnessError",
    "Trajectory",
    "builtin_names",
    "load_scenario",
    "plan",
    "simulate",
    "stiffness",
]
__version__ = "0.1.0"


def __getattr__(name: str) -> Any:
    """The names that need MuJoCo, imported on first use."""
    if name == "Controller":
        from gaitshift.control.controller import Controller

        return Controller
    if name in ("SensorFrame", "MotorCommand"):
        from gaitshift.control import frames

        return getattr(frames, name)
    if name == "simulate":
        from gaitshift.sim.scenario_run import simulate_scenario

        return simulate_scenario
    raise AttributeError(f"module 'gaitshift' has no attribute {name!r}")
