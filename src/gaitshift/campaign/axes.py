"""The axes a campaign can sweep: name -> kind, default and the check of one value (:data:`AXES`).

A case is one value per axis (:mod:`gaitshift.campaign.cases`); an axis the spec leaves out keeps
its default. Units: speed m/s (the scenario's forward command, scaled), yaw rate rad/s, push impulse
N s, push direction degrees in the ground plane (0 = +x forward, 90 = +y left: a lateral push), push
time s of plan time, push duration s, mass scale (factor on the simulated robot's masses only),
friction (floor coefficient), latency ticks (sensing + actuation delay), noise (sensor noise profile)
and its factor, state (what the controller sees), contact (its contact sensing), terrain (``flat`` only), seed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from gaitshift.errors import InputError
from gaitshift.scenario.sim_settings import (
    CONTACT_SOURCES,
    FRICTION_RANGE,
    LATENCY_RANGE,
    NOISE_PROFILES,
    NOISE_SCALE_RANGE,
    STATE_SOURCES,
)

__all__ = ["AXES", "TERRAINS", "Axis", "check_value"]

#: terrains the simulator has today
TERRAINS = ("flat",)
#: gaits of a locomotion scenario
GAITS = ("auto", "walk", "run")


@dataclass(frozen=True)
class Axis:
    """One sweepable parameter: ``kind`` is "float", "int" or "str"; ``low``/``high`` bound numbers
    (inclusive); ``choices`` bound strings (None: any non-empty string); ``default`` when not swept."""

    kind: str
    default: Any
    doc: str
    low: float = -math.inf
    high: float = math.inf
    choices: tuple[str, ...] | None = None


#: every axis of a campaign spec (module docstring)
AXES: dict[str, Axis] = {
    "robot": Axis("str", None, "robot name or YAML (default: the scenario's robot, else g1)"),
    "scenario": Axis("str", "g1-walk", "built-in scenario name or YAML path (relative to the spec)"),
    "gait": Axis("str", None, "locomotion scenarios: gait", choices=GAITS),
    "speed": Axis("float", None, "locomotion scenarios: largest forward command, m/s", 0.0, 20.0),
    "yaw_rate": Axis("float", None, "locomotion scenarios: yaw rate of every velocity command, rad/s", -20, 20),
    "push_impulse": Axis("float", 0.0, "impulse of one push on the pelvis, N s", 0.0, 1000.0),
    "push_direction": Axis("float", 90.0, "push direction in the ground plane, deg (90 = +y)", -360, 360),
    "push_time": Axis("float", 1.5, "push start, s of plan time", 0.0, 3600.0),
    "push_duration": Axis("float", 0.1, "push duration, s", 0.002, 2.0),
    "mass_scale": Axis("float", 1.0, "factor on the simulated robot's masses", 0.25, 4.0),
    "friction": Axis("float", None, "floor friction coefficient", *FRICTION_RANGE),
    "latency": Axis("int", 0, "actuation + sensing delay, ticks", *LATENCY_RANGE),
    "noise": Axis("str", "typical", "sensor noise profile", choices=NOISE_PROFILES),
    "noise_scale": Axis("float", 1.0, "factor on every sensor noise", *NOISE_SCALE_RANGE),
    "state": Axis("str", "estimated", "what the controller sees (as simulate: the estimate)", choices=STATE_SOURCES),
    "contact": Axis("str", None, "contact sensing (default: the robot's sensors)", choices=CONTACT_SOURCES),
    "terrain": Axis("str", "flat", "terrain", choices=TERRAINS),
    "seed": Axis("int", 0, "seed of every random draw of the run", 0, 2**32 - 1),
}


def _number(axis: Axis, field: str, value: Any) -> int | float:
    is_num = isinstance(value, int | float) and not isinstance(value, bool)
    if axis.kind == "int" and not (is_num and float(value).is_integer()):
        raise InputError(field, value, f"an integer in [{axis.low:g}, {axis.high:g}]")
    if not is_num or not math.isfinite(value) or not axis.low <= value <= axis.high:
        raise InputError(field, value, f"a number in [{axis.low:g}, {axis.high:g}]")
    return int(value) if axis.kind == "int" else float(value)


def check_value(name: str, field: str, value: Any) -> Any:
    """``value`` of axis ``name`` checked and normalised (ints for int axes, floats for float axes).

    Raises:
        InputError: naming ``field`` (``axes.push_impulse[2]``), the value and what is allowed.
    """
    axis = AXES[name]
    if axis.kind != "str":
        return _number(axis, field, value)
    if axis.choices is not None and value not in axis.choices:
        raise InputError(field, value, "one of: " + ", ".join(axis.choices))
    if not isinstance(value, str) or not value:
        raise InputError(field, value, "a non-empty string")
    return value
