"""gaitshift: walking, running and walk-run transitions for biped robots.

Public API::

    import gaitshift
    sc = gaitshift.load_scenario("paper001-table2-walk-run-walk")
    traj = gaitshift.plan(sc)            # -> Trajectory (file contract of gaitshift.trajectory)
    traj.save("plan.npz")
    k = gaitshift.stiffness(0.95, 0.4, 0.15, 0.15)   # T_w, T_r, v_r, T_t0, T_t1
"""

from __future__ import annotations

from typing import Any

from .errors import GaitshiftError, InfeasibleError, InputError, ScenarioError, StiffnessError
from .scenario import builtin_names, load_scenario
from .stiffness import Stiffness, stiffness
from .trajectory import Trajectory

__all__ = [
    "GaitshiftError", "InfeasibleError", "InputError", "ScenarioError", "StiffnessError",
    "Stiffness", "Trajectory", "builtin_names", "load_scenario", "plan", "stiffness",
]
__version__ = "0.1.0"


def plan(scenario: Any) -> Trajectory:
    """Plan a scenario (object, built-in name or YAML path) with the planner it names."""
    if not hasattr(scenario, "planner"):
        scenario = load_scenario(scenario)
    if scenario.planner == "tvlip":
        from .planners.tvlip import plan_scenario
    elif scenario.planner == "vhip":
        from .planners.online import plan_scenario  # type: ignore[no-redef]
    else:  # pragma: no cover - the schema admits no other value
        raise InputError("planner", scenario.planner, "tvlip or vhip")
    return plan_scenario(scenario)
