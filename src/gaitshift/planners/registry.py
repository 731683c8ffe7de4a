"""The planner registry: scenario ``planner`` name -> the function that plans it.

Every planner takes a validated scenario and returns a :class:`~gaitshift.trajectory.contract.Trajectory`.
Adding a planner is one row here plus its scenario schema; nothing dispatches on names elsewhere.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from typing import Any

from gaitshift.errors import check_choice
from gaitshift.trajectory.contract import Trajectory

#: planner name -> "module:function" (imported on first use, so that a planner's cost is paid only
#: when it runs)
PLANNERS: dict[str, str] = {
    "tvlip": "gaitshift.planners.tvlip.planner:plan_scenario",
    "vhip": "gaitshift.planners.vhip.generator:plan_scenario",
    "locomotion": "gaitshift.planners.locomotion.plan:plan_scenario",
}


def planner_for(name: str) -> Callable[[Any], Trajectory]:
    """The plan function registered under ``name``.

    Raises:
        InputError: no planner of that name.
    """
    check_choice("planner", name, PLANNERS)
    module, func = PLANNERS[name].split(":")
    fn: Callable[[Any], Trajectory] = getattr(importlib.import_module(module), func)
    return fn
