"""The axes a campaign can sweep: name -> kind, default and the check of one value (:data:`AXES`).

A case is one value per axis (:mod:`gaitshift.campaign.cases`); an axis the spec leaves out keeps
its default. Units: speed m/s (the scenario's forward command, scaled), yaw rate rad/s, push impulse
N s, or push velocity m/s (the impulse that changes the simulated robot's momentum by its mass
times this speed, as the RL anchors state their pushes), push direction degrees in the ground plane
(0 = +x forward, 90 = +y left: a lateral push), push time s of plan time, push duration s, mass
scale (factor on the simulated robot's masses only), base CoM offset m (x, y, z in the base frame)
and motor strength (factor on the motors' torque), the last three on the simulated robot only,
friction (floor coefficient), latency ticks (sensing + actuation delay), noise (sensor noise profile)
and its factor, state (what the controller sees), contact (its contact sensing), terrain (what the
planner is told of the scenario's terrain: known, blind or perceived, as ``simulate --terrain``; the
world is always built on it), seed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from gaitshift.errors import InputError, check_choice
from gaitshift.scenario.sim_settings import (
    COM_OFFSET_RANGE,
    CONTACT_SOURCES,
    FRICTION_RANGE,
    LATENCY_RANGE,
    MOTOR_STRENGTH_RANGE,
    NOISE_PROFILES,
    NOISE_SCALE_RANGE,
    STATE_SOURCES,
    TERRAIN_KNOWLEDGE,
)

__all__ = ["AXES", "EXCLUSIVE", "SIMULATED_ONLY", "Axis", "check_exclusive", "check_simulated", "check_value"]

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
    "push_velocity": Axis("float", 0.0, "push as a base velocity change, m/s (impulse = mass x this)", 0.0, 10.0),
    "push_direction": Axis("float", 90.0, "push direction in the ground plane, deg (90 = +y)", -360, 360),
    "push_time": Axis("float", 1.5, "push start, s of plan time", 0.0, 3600.0),
    "push_duration": Axis("float", 0.1, "push duration, s", 0.002, 2.0),
    "mass_scale": Axis("float", 1.0, "factor on the simulated robot's masses", 0.25, 4.0),
    "com_offset_x": Axis("float", 0.0, "simulated base CoM offset along base x, m", *COM_OFFSET_RANGE),
    "com_offset_y": Axis("float", 0.0, "simulated base CoM offset along base y, m", *COM_OFFSET_RANGE),
    "com_offset_z": Axis("float", 0.0, "simulated base CoM offset along base z, m", *COM_OFFSET_RANGE),
    "motor_strength": Axis("float", 1.0, "factor on the simulated motors' torque", *MOTOR_STRENGTH_RANGE),
    "friction": Axis("float", None, "floor friction coefficient", *FRICTION_RANGE),
    "latency": Axis("int", 0, "actuation + sensing delay, ticks", *LATENCY_RANGE),
    "noise": Axis("str", "typical", "sensor noise profile", choices=NOISE_PROFILES),
    "noise_scale": Axis("float", 1.0, "factor on every sensor noise", *NOISE_SCALE_RANGE),
    "state": Axis("str", "estimated", "what the controller sees (as simulate: the estimate)", choices=STATE_SOURCES),
    "contact": Axis("str", None, "contact sensing (default: the robot's sensors)", choices=CONTACT_SOURCES),
    "terrain": Axis("str", None, "what the planner is told of the terrain (the scenario's)", choices=TERRAIN_KNOWLEDGE),
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
    if axis.choices is not None:
        check_choice(field, value, axis.choices)
    if not isinstance(value, str) or not value:
        raise InputError(field, value, "a non-empty string")
    return value


#: axes that say the same thing two ways: a spec sweeps at most one of each group away from its default
EXCLUSIVE = (("push_impulse", "push_velocity"),)


def check_exclusive(values: dict[str, list[Any]]) -> None:
    """:class:`InputError` when a spec sweeps two axes of one :data:`EXCLUSIVE` group (both not at
    their defaults), naming the second."""
    for group in EXCLUSIVE:
        swept = [n for n in group if values[n] != [AXES[n].default]]
        if len(swept) > 1:
            raise InputError(
                f"axes.{swept[1]}", values[swept[1]][0], f"no value beside axes.{swept[0]} (one of {group})"
            )


#: axes that only a closed-loop run reads: a plan (task ``plan``, a ``kinematic`` reference) is made on
#: the scenario's terrain, so a value there would be silently ignored
SIMULATED_ONLY = ("terrain",)


def check_simulated(simulates: bool, values: dict[str, list[Any]]) -> None:
    """:class:`InputError` when a spec that does not simulate (``simulates`` False) sweeps an axis of
    :data:`SIMULATED_ONLY` away from its default, naming it."""
    if simulates:
        return
    for name in SIMULATED_ONLY:
        if values[name] != [AXES[name].default]:
            raise InputError(
                f"axes.{name}", values[name][0], "no value unless the task simulates (simulate, closed-loop reference)"
            )
