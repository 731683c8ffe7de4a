"""gaitshift: walking, running and walk-run transitions for biped robots.

Public API::

    import gaitshift
    sc = gaitshift.load_scenario("paper001-table2-walk-run-walk")
    traj = gaitshift.plan(sc)            # -> Trajectory (file contract of gaitshift.trajectory)
    traj.save("plan.npz")
    k = gaitshift.stiffness(0.95, 0.4, 0.15, 0.15)   # T_w, T_r, v_r, T_t0, T_t1
"""

from __future__ import annotations

from gaitshift.api import plan
from gaitshift.errors import GaitshiftError, InfeasibleError, InputError, ScenarioError, StiffnessError
from gaitshift.models.stiffness import Stiffness, stiffness
from gaitshift.scenario import builtin_names, load_scenario
from gaitshift.trajectory.contract import Trajectory

__all__ = [
    "GaitshiftError",
    "InfeasibleError",
    "InputError",
    "ScenarioError",
    "Stiffness",
    "StiffnessError",
    "Trajectory",
    "builtin_names",
    "load_scenario",
    "plan",
    "stiffness",
]
__version__ = "0.1.0"
