"""The cases of a campaign: the cartesian product of its axes (or a sample spec's random draws,
:mod:`gaitshift.campaign.sampling`), each with a stable hash.

A case is a plain dict (it crosses process boundaries; no MuJoCo object ever does): the task, the
spec's run settings (``duration``, ``control_period``, ``reference_mode``, ``reference_rate``) and
one value per axis of :data:`gaitshift.campaign.axes.AXES`. Its hash is the first 16 hex digits of
the SHA-256 of its canonical JSON (sorted keys), so that the same case always has the same hash,
whatever the order of the axes in the spec or the machine: the store's file name and resume key.
An axis whose default changed hashes that default as before (:data:`FORMER_DEFAULTS`).
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
from typing import Any

from gaitshift.campaign.sampling import draw_columns
from gaitshift.campaign.spec import MAX_CASES, CampaignSpec
from gaitshift.errors import InputError

__all__ = ["FORMER_DEFAULTS", "LOCOMOTION_AXES", "case_hash", "expand", "settings_of"]

#: axes that edit a locomotion scenario's command script (other planners have no command to scale)
LOCOMOTION_AXES = ("speed", "yaw_rate", "gait")


def settings_of(spec: CampaignSpec) -> dict[str, Any]:
    """The run settings every case of ``spec`` shares (part of each case and of its hash)."""
    return {
        "task": spec.task,
        "duration": spec.duration,
        "control_period": spec.control_period,
        "reference_mode": spec.reference.mode if spec.task == "reference" else None,
        "reference_rate": spec.reference.rate if spec.task == "reference" else None,
    }


#: axis -> (its default now, the value that default was hashed as before): the ``terrain`` axis was
#: ``flat`` (the only floor) until it said what the planner is told; a case at the default keeps the
#: hash it had, so older stores resume and the hashes named in the docs stay theirs
FORMER_DEFAULTS: dict[str, tuple[Any, Any]] = {"terrain": (None, "flat")}


def case_hash(case: dict[str, Any]) -> str:
    """16 hex digits of SHA-256 over the canonical JSON of ``case`` without its ``case_hash`` (an axis
    at the default of :data:`FORMER_DEFAULTS` counted as its former value)."""
    body = {k: v for k, v in case.items() if k != "case_hash"}
    for name, (now, before) in FORMER_DEFAULTS.items():
        if name in body and body[name] == now:
            body[name] = before
    text = json.dumps(body, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _check_scenarios(spec: CampaignSpec, values: dict[str, list[Any]]) -> None:
    """Every scenario loads, every robot loads, and the locomotion axes meet locomotion scenarios."""
    from gaitshift.robots.config import load_robot
    from gaitshift.scenario import load_scenario

    for robot in values["robot"]:
        if robot is not None:
            load_robot(robot)
    edits = [a for a in LOCOMOTION_AXES if values[a] != [None]]
    for name in values["scenario"]:
        sc = load_scenario(spec.scenario_path(name))
        if edits and sc.planner != "locomotion":
            raise InputError(
                f"axes.{edits[0]}", values[edits[0]][0], f"scenarios with planner: locomotion ({name} is {sc.planner})"
            )
        if spec.duration is not None and sc.planner != "locomotion":
            raise InputError("duration", spec.duration, f"no value unless every scenario is locomotion ({name})")


def expand(spec: CampaignSpec, check: bool = True) -> list[dict[str, Any]]:
    """The cases of ``spec`` in product order (the last axis varies fastest) or, for a sample spec,
    in draw order, each with its ``case_hash``; with ``check``, scenarios and robots are loaded once
    to validate them.

    Raises:
        InputError: a bad axis value, scenario or robot (see :meth:`CampaignSpec.axis_values`).
    """
    values = spec.axis_values()
    count = spec.sample.cases if spec.sample is not None else math.prod(len(v) for v in values.values())
    if count > MAX_CASES:
        sizes = " x ".join(f"{n} {len(v)}" for n, v in values.items() if len(v) > 1)
        raise InputError("axes", f"{count:.3g} cases ({sizes})", f"at most {MAX_CASES:,} cases per campaign")
    if check:
        _check_scenarios(spec, values)
    names = list(values)
    base = settings_of(spec)
    if spec.sample is not None:
        cols = draw_columns(spec, values)
        combos: Any = zip(*(cols[n] for n in names), strict=True)
    else:
        combos = itertools.product(*(values[n] for n in names))
    cases = []
    for combo in combos:
        case = base | dict(zip(names, combo, strict=True))
        case["case_hash"] = case_hash(case)
        cases.append(case)
    return cases
