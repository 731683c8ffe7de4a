"""The TV-LIPM scenario of paper 001 (``planner: tvlip``): timings, gait layout and footsteps."""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

from pydantic import Field, Strict, ValidationInfo, field_validator

from gaitshift.scenario.fields import (
    ComHeight,
    Count,
    Duration,
    Foot,
    Gravity,
    Length,
    NonNegLength,
    Real,
    SignedLength,
    StandDuration,
    StrictModel,
    check_samples,
)
from gaitshift.scenario.sim_settings import SimSettings
from gaitshift.scenario.terrain import TerrainPiece, check_pieces


class Timing(StrictModel):
    """Phase durations, s. ``start``/``stop`` are the standing double-support phases that begin and
    end a plan (CoM at rest over the feet)."""

    single_support: Duration = 0.4
    double_support: Duration = 0.15
    flight: Duration = 0.15
    start: StandDuration = 0.8
    stop: StandDuration = 1.0


class Segment(StrictModel):
    """A run of consecutive steps with one gait."""

    gait: Literal["walk", "run"]
    steps: Annotated[int, Strict(), Field(ge=1, le=100_000)]


class StrideProfile(StrictModel):
    """Footsteps from a stride-length profile: stride ramps up linearly over ``accelerate_steps``,
    holds ``max_stride``, ramps down over ``decelerate_steps``. Stride is the forward distance between
    consecutive footholds (left to right), m. ``yaw_rate`` turns the path by that many rad per step
    (at most pi); ``step_height`` raises each foothold by that many m (stairs)."""

    max_stride: Length = 0.5
    accelerate_steps: Count = 8
    decelerate_steps: Count = 8
    step_width: Length = 0.2
    yaw_rate: Annotated[float, Strict(), Field(ge=-math.pi, le=math.pi, allow_inf_nan=False)] = 0.0
    step_height: SignedLength = 0.0


class Limits(StrictModel):
    """What the robot can reach: the longest stride and largest per-step rise, m."""

    max_stride: Length = 1.0
    max_step_height: NonNegLength = 0.25


class TvlipScenario(StrictModel):
    """A TV-LIPM plan over given footsteps (paper 001 §II-B)."""

    planner: Literal["tvlip"] = "tvlip"
    name: str = "custom"
    sim: SimSettings = SimSettings()  # how `gaitshift simulate` runs it (scenario/sim_settings.py)
    description: str = ""
    gravity: Gravity = 9.81
    height: ComHeight = 0.95
    #: the robot this scenario is made for (built-in name or robot YAML path): what `gaitshift simulate`
    #: runs it on (docs/robots.md); the plan itself takes every number from the scenario
    robot: str | None = None
    timing: Timing = Timing()
    foot: Foot = Foot()
    gait: tuple[Segment, ...] = (Segment(gait="walk", steps=6),)
    first_swing: Literal["left", "right"] = "right"
    profile: StrideProfile = StrideProfile()
    #: Explicit footholds [x, y, z, yaw] for each step, replacing ``profile``; z is measured from the
    #: ``terrain`` under the sole centre (0: on the ground, gait/footsteps.py ``on_terrain``). The two
    #: initial feet are at (0, +/- step_width/2, 0); the last foothold is followed by a closing step beside it.
    footsteps: tuple[tuple[Real, Real, Real, Real], ...] | None = None
    limits: Limits = Limits()
    #: the ground under the footholds (scenario/terrain.py); empty: the flat floor
    terrain: tuple[TerrainPiece, ...] = ()
    swing_height: NonNegLength = 0.08
    #: height kept between a swinging sole and the terrain edges it passes over, m (gait/swing.py)
    edge_clearance: NonNegLength = 0.03
    dt: Annotated[float, Strict(), Field(ge=1e-4, le=0.05, allow_inf_nan=False, validate_default=True)] = 0.001

    @property
    def n_steps(self) -> int:
        return sum(s.steps for s in self.gait)

    @field_validator("footsteps")
    @classmethod
    def _one_per_step(cls, v: tuple[tuple[float, ...], ...] | None, info: ValidationInfo) -> Any:
        gait = info.data.get("gait")
        if v is not None and gait is not None and len(v) != sum(s.steps for s in gait):
            raise ValueError(f"one foothold per step of gait ({sum(s.steps for s in gait)}), not {len(v)}")
        return v

    @field_validator("terrain")
    @classmethod
    def _terrain_sorted(cls, v: tuple[TerrainPiece, ...]) -> tuple[TerrainPiece, ...]:
        check_pieces(v)
        return v

    @field_validator("dt")
    @classmethod
    def _samples(cls, v: float, info: ValidationInfo) -> float:
        if "timing" in info.data and "gait" in info.data:
            check_samples(duration(info.data["timing"], info.data["gait"]), v)
        return v


def duration(timing: Timing, gait: tuple[Segment, ...]) -> float:
    """Planned time of a gait, s: start + stop + every step (single support plus double support or
    flight) + the closing step."""
    step = {"walk": timing.single_support + timing.double_support, "run": timing.single_support + timing.flight}
    steps = sum(s.steps * step[s.gait] for s in gait)
    return timing.start + timing.stop + steps + timing.single_support + timing.double_support
