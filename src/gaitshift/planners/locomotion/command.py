"""Commands of the locomotion generator: clamping, the per-step ramp, and gait selection.

A command is (vx, vy, yaw_rate): m/s in the robot's heading frame (x forward, y left) and rad/s.
It is clamped to the limits (each clamp is an event). The planner does not jump to it: at every
planning instant the *target* moves toward the applied command by at most ``max_accel`` per step
(the documented per-step acceleration limit), so a step change within that limit is reached in one
planning instant and a larger one ramps.

Gait selection (``auto``) uses the speed ``|v| = hypot(vx, vy)`` of the larger of the target and the
command (:meth:`~gaitshift.planners.locomotion.policy.TargetPolicy.gait_speed`) with hysteresis: walking
switches to running above ``walk_to_run`` (v_up) and running switches back below ``run_to_walk``
(v_down < v_up). A command that hovers between the two keeps the current gait; one oscillating by
less than v_up - v_down around a threshold switches at most once. docs/locomotion.md derives the default
thresholds from the robot's leg length (Froude number).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from numbers import Real
from typing import Any

import numpy as np
import numpy.typing as npt

from gaitshift.errors import InputError
from gaitshift.models.arrays import FloatArray
from gaitshift.planners.locomotion.params import Limits
from gaitshift.planners.locomotion.steps import Gait

__all__ = ["MAX_VALUE", "Clamp", "clamp_command", "finite_real", "next_gait", "ramp"]

NAMES = ("command.vx", "command.vy", "command.yaw_rate")
#: largest magnitude of a command component or a goal coordinate (m/s, rad/s, m, rad) the generator takes
MAX_VALUE = 1e6


def finite_real(field: str, value: Any, allowed: str) -> float:
    """``value`` as a float when it is a real number (not a bool) of magnitude <= :data:`MAX_VALUE`,
    else the :class:`InputError` naming ``field`` (``allowed`` says the unit)."""
    if isinstance(value, bool) or not isinstance(value, Real) or not abs(float(value)) <= MAX_VALUE:
        raise InputError(field, value, f"a finite number of magnitude <= {MAX_VALUE:g} ({allowed})")
    return float(value)


@dataclass(frozen=True)
class Clamp:
    """One clamped component: field name, requested and applied value, and the limit's name."""

    field: str
    requested: float
    applied: float
    reason: str


def clamp_command(cmd: Iterable[Any], limits: Limits, stride_speed: FloatArray) -> tuple[FloatArray, list[Clamp]]:
    """Clamp (vx, vy, yaw_rate) to the limits; return the applied command (3,) and the clamps.

    ``stride_speed`` (3,) holds the largest |vx|, |vy| and |yaw rate| that the foothold limits allow
    for the gait in use (stride, width and turn per step over the step duration).

    Raises:
        InputError: a non-finite component (names the field).
    """
    req = np.array([finite_real(n, v, "m/s for vx, vy; rad/s for yaw_rate") for n, v in zip(NAMES, cmd, strict=True)])
    lo = np.array([-limits.max_speed[1], -limits.max_speed[2], -limits.max_yaw_rate])
    hi = np.array([limits.max_speed[0], limits.max_speed[2], limits.max_yaw_rate])
    names = ["limits.max_speed", "limits.max_speed", "limits.max_yaw_rate"]
    out = np.clip(req, lo, hi)
    why = list(names)
    for i in range(3):
        if abs(out[i]) > stride_speed[i]:
            out[i] = math.copysign(stride_speed[i], out[i])
            why[i] = ("limits.max_stride", "limits.width", "limits.max_turn")[i]
    clamps = [Clamp(NAMES[i], float(req[i]), float(out[i]), why[i]) for i in range(3) if out[i] != req[i]]
    return out, clamps


def ramp(target: FloatArray, command: FloatArray, max_accel: npt.ArrayLike, lead_time: float) -> FloatArray:
    """Move ``target`` (3,) toward ``command`` (3,) by at most ``max_accel`` (3,) per component.

    A yaw-rate change ``d omega`` turns the heading of the planner's target state, ``lead_time`` s
    ahead, by ``d omega lead_time``: at speed |v| the CoM velocity must then turn sideways by about
    ``|v| d omega lead_time`` within the horizon. The yaw-rate step is therefore also limited so
    that this stays within the lateral acceleration limit ``max_accel[1]``."""
    step = np.asarray(max_accel, dtype=np.float64).copy()
    speed = float(np.hypot(target[0], target[1]))
    if speed * lead_time > 0.0:
        step[2] = min(step[2], step[1] / (speed * lead_time))
    return np.asarray(target + np.clip(command - target, -step, step), dtype=np.float64)


def next_gait(current: Gait, speed: float, mode: str, walk_to_run: float, run_to_walk: float) -> Gait:
    """The gait wanted for the next step: fixed by ``mode`` ("walk", "run"), or with hysteresis in
    "auto" (module docstring). ``current`` is the gait of the step being planned."""
    if mode == "walk":
        return Gait.WALK
    if mode == "run":
        return Gait.RUN
    if current == Gait.RUN:
        return Gait.WALK if speed < run_to_walk else Gait.RUN
    return Gait.RUN if speed > walk_to_run else Gait.WALK
