"""The online VHIP running scenario of paper 003 (``planner: vhip``): heights, timing, speed commands."""

from __future__ import annotations

import itertools
from typing import Annotated, Literal

from pydantic import Field, Strict, ValidationInfo, field_validator

from gaitshift.scenario.fields import (
    Accel,
    ComHeight,
    Duration,
    Foot,
    Gravity,
    Length,
    NonNegLength,
    PosSpeed,
    Speed,
    StandDuration,
    StrictModel,
    check_samples,
)
from gaitshift.scenario.sim_settings import SimSettings

#: a time within a run, s (runs are at most 10 minutes)
RunTime = Annotated[float, Strict(), Field(ge=0, le=600, allow_inf_nan=False)]


class VhipHeights(StrictModel):
    """CoM heights of the VHIP running gait (paper 003 eqs. (3)-(6)), m, and the vertical CoM
    accelerations at the contact switches, m/s^2 (``None`` = -gravity: zero ground force at touchdown
    and take-off, so the vertical force is continuous)."""

    stand: ComHeight = 0.80
    touchdown: ComHeight = 0.80
    takeoff: ComHeight = 0.80
    z_low: ComHeight = 0.76
    touchdown_acc: Accel | None = None
    takeoff_acc: Accel | None = None

    @field_validator("z_low")
    @classmethod
    def _squat_below(cls, v: float, info: ValidationInfo) -> float:
        for key in ("takeoff", "touchdown", "stand"):
            other = info.data.get(key)
            if other is not None and not v < other:
                raise ValueError(f"below the {key} height {other} m (the CoM squats in stance)")
        return v


class VhipCommand(StrictModel):
    """A speed command issued at time ``t`` (s): forward ``vx`` and lateral ``vy``, m/s."""

    t: RunTime = 0.0
    vx: Speed = 0.0
    vy: Speed = 0.0


class VhipLimits(StrictModel):
    """Limits of the online generator. Commands beyond them are clamped and reported as events.

    ``max_speed`` [x, y] (m/s); ``max_stride`` largest distance between consecutive footholds along
    each axis (m); ``max_accel_per_step`` [x, y] largest change of the take-off speed target from one
    step to the next (m/s per step)."""

    max_speed: tuple[PosSpeed, PosSpeed] = (1.5, 0.2)
    max_stride: Length = 0.8
    max_accel_per_step: tuple[PosSpeed, PosSpeed] = (0.3, 0.2)


def ticks(value: float, dt: float) -> int | None:
    """``value / dt`` when it is an integer (to 1e-9 relative), else None."""
    n = round(value / dt)
    return n if abs(n * dt - value) <= 1e-9 * max(1.0, value) else None


class VhipScenario(StrictModel):
    """The online VHIP running generator of paper 003: standing start, running with streamed speed
    commands, stop to standstill (see docs/vhip.md)."""

    planner: Literal["vhip"] = "vhip"
    name: str = "custom"
    sim: SimSettings = SimSettings()  # how `gaitshift simulate` runs it (scenario/sim_settings.py)
    description: str = ""
    #: the robot this scenario is made for (built-in name or robot YAML path): what `gaitshift simulate`
    #: runs it on (docs/robots.md); the plan itself takes every number from the scenario
    robot: str | None = None
    gravity: Gravity = 9.81
    #: sample step = control period, s (the paper controls at 4 ms; 1 ms keeps finite differences of the
    #: stance sextic within the file checks)
    dt: Annotated[float, Strict(), Field(ge=1e-4, le=0.02, allow_inf_nan=False)] = 0.001
    #: one running step (stance + flight), s
    step_period: Duration = 0.4
    #: stance share of a step, in (0, 1)
    stance_ratio: Annotated[float, Strict(), Field(gt=0, lt=1, allow_inf_nan=False)] = 0.7
    #: standing double support before the first step (State Switching 1), s
    start_double_support: StandDuration = 1.2
    #: double support after the last step, ending at rest (State Switching 3), s
    stop_double_support: StandDuration = 1.2
    heights: VhipHeights = VhipHeights()
    foot: Foot = Foot()
    #: lateral distance between the two feet centres when standing, m
    step_width: Length = 0.2
    first_support: Literal["left", "right"] = "left"
    #: scripted speed commands, in time order
    commands: tuple[VhipCommand, ...] = (VhipCommand(),)
    #: time of the stop request, s (None: 2 s after the last command); runs are at most 10 minutes
    stop_at: Annotated[RunTime | None, Field(validate_default=True)] = None
    limits: VhipLimits = VhipLimits()
    #: swing-foot apex above the higher end, m
    swing_apex: NonNegLength = 0.08

    @field_validator("step_period", "start_double_support", "stop_double_support")
    @classmethod
    def _multiple_of_dt(cls, v: float, info: ValidationInfo) -> float:
        dt = info.data.get("dt")
        if dt is not None:
            n = ticks(v, dt)
            if n is None:
                raise ValueError(f"a multiple of dt = {dt} s")
            if n < 4:
                raise ValueError(f">= 4 dt = {4 * dt:g} s")
        return v

    @field_validator("stance_ratio")
    @classmethod
    def _phases_fit(cls, v: float, info: ValidationInfo) -> float:
        dt, step = info.data.get("dt"), info.data.get("step_period")
        if dt is not None and step is not None:
            n_sup = ticks(v * step, dt)
            if n_sup is None:
                raise ValueError(f"a ratio making the stance ({v * step:g} s) a multiple of dt = {dt} s")
            n_fly = round(step / dt) - n_sup
            if n_sup < 4 or n_fly < 2:
                raise ValueError(
                    f"a stance of >= 4 dt and a flight of >= 2 dt (got stance {n_sup} dt, flight {n_fly} dt)"
                )
        return v

    @field_validator("heights")
    @classmethod
    def _ground_pushes(cls, v: VhipHeights, info: ValidationInfo) -> VhipHeights:
        from gaitshift.models.vhip import stance_profiles  # lazy: the schema stays importable on its own

        d = info.data
        if all(k in d for k in ("gravity", "dt", "step_period", "stance_ratio")):
            stance_profiles(
                v, d["gravity"], d["step_period"] * d["stance_ratio"], d["step_period"] * (1 - d["stance_ratio"])
            )
        return v

    @field_validator("commands")
    @classmethod
    def _in_time_order(cls, v: tuple[VhipCommand, ...]) -> tuple[VhipCommand, ...]:
        if len(v) == 0:
            raise ValueError("at least one command")
        times = [c.t for c in v]
        if any(b < a for a, b in itertools.pairwise(times)):
            raise ValueError(f"commands in time order (got t = {times})")
        return v

    @field_validator("stop_at")
    @classmethod
    def _samples(cls, v: float | None, info: ValidationInfo) -> float | None:
        d = info.data
        if all(k in d for k in ("dt", "step_period", "start_double_support", "stop_double_support", "commands")):
            stop = v if v is not None else max(c.t for c in d["commands"]) + 2.0
            ramp = 10.0  # allowance for the ramp down to rest after the stop request, s
            check_samples(d["start_double_support"] + stop + ramp + d["stop_double_support"], d["dt"])
        return v

    @property
    def n_step(self) -> int:
        """Samples per running step."""
        return round(self.step_period / self.dt)
