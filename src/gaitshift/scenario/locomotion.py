"""Schema of ``planner: locomotion`` scenarios: the online walk/run/turn/stop generator driven by a
scripted command stream (docs/locomotion.md).

Only ``planner``, ``gait``, ``switch``, ``commands`` and ``stop_at`` are needed; every other key has
a default taken from the robot named by ``robot`` (its CoM height, leg length, soles and foot
separation, with paper 001's timings Froude-scaled to it) or, without a robot, from paper 001
(h = 0.95 m, Table II timings). ``None`` in the schema means "use that default"; the resolution
into numbers is :func:`gaitshift.planners.locomotion.params.params_from_scenario`.
"""

from __future__ import annotations

import itertools
from typing import Annotated, Literal

from pydantic import Field, Strict, model_validator

from gaitshift.scenario.fields import (
    ComHeight,
    Duration,
    Gravity,
    Length,
    NonNegLength,
    PosSpeed,
    Real,
    SoleSide,
    Speed,
    StandDuration,
    StrictModel,
    check_samples,
)
from gaitshift.scenario.sim_settings import SimSettings
from gaitshift.scenario.terrain import TerrainPiece, check_pieces

__all__ = ["Goto", "LocomotionCommand", "LocomotionLimits", "LocomotionScenario", "LocomotionTiming", "Switch"]

#: a time of the command script, s (runs of at most an hour)
Time = Annotated[float, Strict(), Field(ge=0, le=3600, allow_inf_nan=False)]
#: a yaw rate, rad/s
YawRate = Annotated[float, Strict(), Field(ge=-20, le=20, allow_inf_nan=False)]
#: a positive yaw rate or per-step change, rad/s or rad
PosYaw = Annotated[float, Strict(), Field(gt=0, le=20, allow_inf_nan=False)]
_Strict = StrictModel


class LocomotionTiming(_Strict):
    """Phase durations, s (multiples of dt). Walking single support ``walk_single``; running (and
    transition) single support ``run_single``; ``double`` support; ``flight``; the standing double
    supports ``start`` (before the first step) and ``stop`` (after the closing step)."""

    walk_single: Duration | None = None
    double: Duration | None = None
    run_single: Duration | None = None
    flight: Duration | None = None
    start: StandDuration | None = None
    stop: StandDuration | None = None


class Switch(_Strict):
    """Walk/run hysteresis thresholds, m/s: walk -> run above ``walk_to_run``, run -> walk below
    ``run_to_walk`` (< walk_to_run). Defaults from the Froude number (docs/locomotion.md)."""

    walk_to_run: PosSpeed | None = None
    run_to_walk: PosSpeed | None = None

    @model_validator(mode="after")
    def _ordered(self) -> Switch:
        if self.walk_to_run is not None and self.run_to_walk is not None and not self.run_to_walk < self.walk_to_run:
            raise ValueError(f"run_to_walk = {self.run_to_walk} below walk_to_run = {self.walk_to_run} (hysteresis)")
        return self


class LocomotionLimits(_Strict):
    """Command and foothold limits (defaults scale with the robot, docs/locomotion.md).

    ``max_speed`` [forward, backward, lateral] m/s; ``max_yaw_rate`` rad/s; ``max_accel`` per step
    [vx m/s, vy m/s, yaw rate rad/s]; ``max_stride`` largest forward/backward foot displacement per
    step, m; ``width`` [min, max] lateral distance between consecutive feet, m; ``max_turn`` largest
    foot yaw change per step, rad."""

    max_speed: tuple[PosSpeed, PosSpeed, PosSpeed] | None = None
    max_yaw_rate: PosYaw | None = None
    max_accel: tuple[PosSpeed, PosSpeed, PosYaw] | None = None
    max_stride: Length | None = None
    width: tuple[Length, Length] | None = None
    max_turn: PosYaw | None = None

    @model_validator(mode="after")
    def _width_ordered(self) -> LocomotionLimits:
        if self.width is not None and not self.width[0] < self.width[1]:
            raise ValueError(f"width = {list(self.width)}: the minimum must be below the maximum")
        return self


class Goto(_Strict):
    """A goal pose in the world frame: position (m) and yaw (rad)."""

    x: Real
    y: Real
    yaw: Real = 0.0


class LocomotionCommand(_Strict):
    """From time ``t`` (s) on: the velocity command (vx, vy m/s in the heading frame; yaw_rate rad/s),
    or a goal pose (``goto``) that the generator walks to and stops on."""

    t: Time = 0.0
    vx: Speed = 0.0
    vy: Speed = 0.0
    yaw_rate: YawRate = 0.0
    goto: Goto | None = None

    @model_validator(mode="after")
    def _one_kind(self) -> LocomotionCommand:
        if self.goto is not None and (self.vx or self.vy or self.yaw_rate):
            raise ValueError("either a velocity (vx, vy, yaw_rate) or a goto, not both")
        return self


class Foot(_Strict):
    """Sole [length, width] in m and the ZMP margin kept inside it in the start and stop, m."""

    size: tuple[SoleSide, SoleSide] | None = None
    zmp_margin: NonNegLength | None = None


class LocomotionScenario(_Strict):
    """A locomotion scenario (module docstring)."""

    planner: Literal["locomotion"] = "locomotion"
    name: str = "custom"
    sim: SimSettings = SimSettings()  # how `gaitshift simulate` runs it (scenario/sim_settings.py)
    description: str = ""
    robot: str | None = None
    gait: Literal["auto", "walk", "run"] = "auto"
    switch: Switch = Switch()
    commands: tuple[LocomotionCommand, ...] = (LocomotionCommand(),)
    stop_at: Time | None = None
    gravity: Gravity = 9.81
    height: ComHeight | None = None
    leg_length: Length | None = None
    timing: LocomotionTiming = LocomotionTiming()
    foot: Foot = Foot()
    step_width: Length | None = None
    swing_height: NonNegLength | None = None
    first_swing: Literal["left", "right"] = "right"
    limits: LocomotionLimits = LocomotionLimits()
    dt: Annotated[float, Strict(), Field(ge=1e-4, le=0.01, allow_inf_nan=False)] = 0.001
    #: the ground of the simulated world (scenario/terrain.py); the generator plans on flat ground, so
    #: such a scenario runs with ``sim: {terrain: blind}`` until it plans on what it perceives (issue 29)
    terrain: tuple[TerrainPiece, ...] = ()

    @model_validator(mode="after")
    def _commands_in_order(self) -> LocomotionScenario:
        check_pieces(self.terrain)
        times = [c.t for c in self.commands]
        if not times:
            raise ValueError("at least one command")
        if any(b < a for a, b in itertools.pairwise(times)):
            raise ValueError(f"commands in time order (got t = {times})")
        end = self.stop_at if self.stop_at is not None else times[-1] + 3.0
        check_samples(end + 60.0, self.dt)
        return self
