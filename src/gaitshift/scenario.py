"""Scenario schema (pydantic) and the loader for built-in names and YAML files.

A scenario is everything a planner needs: the robot-independent CoM height, timings, foot size, the
gait layout and the footsteps. ``planner`` selects the schema: ``tvlip`` (paper 001) or ``vhip``
(paper 003). Built-in scenarios are YAML files shipped in ``gaitshift/scenarios``.

Every validation failure becomes one :class:`~gaitshift.errors.ScenarioError` that names the dotted
field, the value and what is allowed.
"""

from __future__ import annotations

import math
from importlib import resources
from pathlib import Path
from typing import Annotated, Any, Literal, Union

import yaml
from pydantic import BaseModel, ConfigDict, Field, TypeAdapter, ValidationError, model_validator

from .errors import ScenarioError

Pos = Annotated[float, Field(gt=0, allow_inf_nan=False)]
NonNeg = Annotated[float, Field(ge=0, allow_inf_nan=False)]
Real = Annotated[float, Field(allow_inf_nan=False)]


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


# ============================================================================ TV-LIPM (paper 001)
class Timing(_Strict):
    """Phase durations, s. ``start``/``stop`` are the standing double-support phases that begin and
    end a plan (CoM at rest over the feet)."""

    single_support: Pos = 0.4
    double_support: Pos = 0.15
    flight: Pos = 0.15
    start: Pos = 0.8
    stop: Pos = 1.0


class Foot(_Strict):
    """Sole rectangle [length, width] in m, and the margin by which the ZMP box of eq. (7) of 001 is
    shrunk inside it. ``zmp_z`` is the allowed vertical offset of the 3D ZMP from the sole plane."""

    size: tuple[Pos, Pos] = (0.22, 0.12)
    zmp_margin: NonNeg = 0.01
    zmp_z: tuple[Real, Real] = (0.0, 0.0)

    @model_validator(mode="after")
    def _margin_fits(self) -> "Foot":
        if 2 * self.zmp_margin >= min(self.size):
            raise ValueError(f"zmp_margin={self.zmp_margin} leaves no ZMP area in a sole of {list(self.size)}")
        if self.zmp_z[0] > self.zmp_z[1]:
            raise ValueError(f"zmp_z lower bound {self.zmp_z[0]} exceeds upper bound {self.zmp_z[1]}")
        return self


class Segment(_Strict):
    """A run of consecutive steps with one gait."""

    gait: Literal["walk", "run"]
    steps: Annotated[int, Field(ge=1, le=100000)]


class StrideProfile(_Strict):
    """Footsteps from a stride-length profile: stride ramps up linearly over ``accelerate_steps``,
    holds ``max_stride``, ramps down over ``decelerate_steps``. Stride is the forward distance between
    consecutive footholds (left to right), m. ``yaw_rate`` turns the path by that many rad per step;
    ``step_height`` raises each foothold by that many m (stairs)."""

    max_stride: Pos = 0.5
    accelerate_steps: Annotated[int, Field(ge=0)] = 8
    decelerate_steps: Annotated[int, Field(ge=0)] = 8
    step_width: Pos = 0.2
    yaw_rate: Real = 0.0
    step_height: Real = 0.0


class Limits(_Strict):
    """What the robot can reach: the longest stride and largest per-step rise, m."""

    max_stride: Pos = 1.0
    max_step_height: NonNeg = 0.25


class TvlipScenario(_Strict):
    """A TV-LIPM plan over given footsteps (paper 001 §II-B)."""

    planner: Literal["tvlip"] = "tvlip"
    name: str = "custom"
    description: str = ""
    gravity: Pos = 9.81
    height: Pos = 0.95
    timing: Timing = Timing()
    foot: Foot = Foot()
    gait: tuple[Segment, ...] = (Segment(gait="walk", steps=6),)
    first_swing: Literal["left", "right"] = "right"
    profile: StrideProfile = StrideProfile()
    #: Explicit footholds [x, y, z, yaw] for each step, replacing ``profile``. The two initial feet are
    #: at (0, +/- step_width/2, 0); the last foothold is followed by a closing step beside it.
    footsteps: tuple[tuple[Real, Real, Real, Real], ...] | None = None
    limits: Limits = Limits()
    swing_height: NonNeg = 0.08
    dt: Annotated[float, Field(gt=0, le=0.05, allow_inf_nan=False)] = 0.001

    @property
    def n_steps(self) -> int:
        return sum(s.steps for s in self.gait)

    @model_validator(mode="after")
    def _consistent(self) -> "TvlipScenario":
        if self.footsteps is not None and len(self.footsteps) != self.n_steps:
            raise ValueError(f"footsteps has {len(self.footsteps)} entries but gait has {self.n_steps} steps")
        return self


# ============================================================================ VHIP (paper 003)
# (the online generator's schema, class VhipScenario, goes here)
from pydantic import ValidationInfo, field_validator  # noqa: E402  (used by the VHIP schema only)


class VhipHeights(_Strict):
    """CoM heights of the VHIP running gait (paper 003 eqs. (3)-(6)), m, and the vertical CoM
    accelerations at the contact switches, m/s^2 (``None`` = -gravity: zero ground force at touchdown
    and take-off, so the vertical force is continuous)."""

    stand: Pos = 0.80
    touchdown: Pos = 0.80
    takeoff: Pos = 0.80
    z_low: Pos = 0.76
    touchdown_acc: Annotated[float, Field(allow_inf_nan=False)] | None = None
    takeoff_acc: Annotated[float, Field(allow_inf_nan=False)] | None = None

    @field_validator("z_low")
    @classmethod
    def _squat_below(cls, v: float, info: ValidationInfo) -> float:
        for key in ("takeoff", "touchdown", "stand"):
            other = info.data.get(key)
            if other is not None and not v < other:
                raise ValueError(f"below the {key} height {other} m (the CoM squats in stance)")
        return v


class VhipCommand(_Strict):
    """A speed command issued at time ``t`` (s): forward ``vx`` and lateral ``vy``, m/s."""

    t: Annotated[float, Field(ge=0, le=600, allow_inf_nan=False)] = 0.0
    vx: Real = 0.0
    vy: Real = 0.0


class VhipLimits(_Strict):
    """Limits of the online generator. Commands beyond them are clamped and reported as events.

    ``max_speed`` [x, y] (m/s); ``max_stride`` largest distance between consecutive footholds along
    each axis (m); ``max_accel_per_step`` [x, y] largest change of the take-off speed target from one
    step to the next (m/s per step)."""

    max_speed: tuple[Pos, Pos] = (1.5, 0.2)
    max_stride: Pos = 0.8
    max_accel_per_step: tuple[Pos, Pos] = (0.3, 0.2)


def _ticks(value: float, dt: float) -> int | None:
    n = round(value / dt)
    return n if abs(n * dt - value) <= 1e-9 * max(1.0, value) else None


class VhipScenario(_Strict):
    """The online VHIP running generator of paper 003: standing start, running with streamed speed
    commands, stop to standstill (see docs/vhip.md)."""

    planner: Literal["vhip"] = "vhip"
    name: str = "custom"
    description: str = ""
    gravity: Pos = 9.81
    #: sample step = control period, s (the paper controls at 4 ms; 1 ms keeps finite differences of the
    #: stance sextic within the file checks)
    dt: Annotated[float, Field(gt=0, le=0.02, allow_inf_nan=False)] = 0.001
    #: one running step (stance + flight), s
    step_period: Pos = 0.4
    #: stance share of a step, in (0, 1)
    stance_ratio: Annotated[float, Field(gt=0, lt=1, allow_inf_nan=False)] = 0.7
    #: standing double support before the first step (State Switching 1), s
    start_double_support: Pos = 1.2
    #: double support after the last step, ending at rest (State Switching 3), s
    stop_double_support: Pos = 1.2
    heights: VhipHeights = VhipHeights()
    foot: Foot = Foot()
    #: lateral distance between the two feet centres when standing, m
    step_width: Pos = 0.2
    first_support: Literal["left", "right"] = "left"
    #: scripted speed commands, in time order
    commands: tuple[VhipCommand, ...] = (VhipCommand(),)
    #: time of the stop request, s (None: 2 s after the last command); runs are at most 10 minutes
    stop_at: Annotated[float, Field(ge=0, le=600, allow_inf_nan=False)] | None = None
    limits: VhipLimits = VhipLimits()
    #: swing-foot apex above the higher end, m
    swing_apex: NonNeg = 0.08

    @field_validator("step_period", "start_double_support", "stop_double_support")
    @classmethod
    def _multiple_of_dt(cls, v: float, info: ValidationInfo) -> float:
        dt = info.data.get("dt")
        if dt is not None:
            n = _ticks(v, dt)
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
            n_sup = _ticks(v * step, dt)
            if n_sup is None:
                raise ValueError(f"a ratio making the stance ({v * step:g} s) a multiple of dt = {dt} s")
            n_fly = round(step / dt) - n_sup
            if n_sup < 4 or n_fly < 2:
                raise ValueError(f"a stance of >= 4 dt and a flight of >= 2 dt (got stance {n_sup} dt, "
                                 f"flight {n_fly} dt)")
        return v

    @field_validator("heights")
    @classmethod
    def _ground_pushes(cls, v: VhipHeights, info: ValidationInfo) -> VhipHeights:
        from .models.vhip import stance_profiles  # lazy: the schema stays importable on its own

        d = info.data
        if all(k in d for k in ("gravity", "dt", "step_period", "stance_ratio")):
            stance_profiles(v, d["gravity"], d["step_period"] * d["stance_ratio"],
                            d["step_period"] * (1 - d["stance_ratio"]))
        return v

    @field_validator("commands")
    @classmethod
    def _in_time_order(cls, v: tuple[VhipCommand, ...]) -> tuple[VhipCommand, ...]:
        if len(v) == 0:
            raise ValueError("at least one command")
        times = [c.t for c in v]
        if any(b < a for a, b in zip(times, times[1:])):
            raise ValueError(f"commands in time order (got t = {times})")
        return v

    @property
    def n_stance(self) -> int:
        """Stance samples per step."""
        return round(self.step_period * self.stance_ratio / self.dt)

    @property
    def n_step(self) -> int:
        """Samples per running step."""
        return round(self.step_period / self.dt)


Scenario = Annotated[Union[TvlipScenario, VhipScenario], Field(discriminator="planner")]
_ADAPTER: TypeAdapter[Any] = TypeAdapter(Scenario)
SCHEMAS: dict[str, type[BaseModel]] = {"tvlip": TvlipScenario, "vhip": VhipScenario}


# ============================================================================ loading
def builtin_names() -> list[str]:
    """Names of the built-in scenarios, sorted."""
    folder = resources.files("gaitshift") / "scenarios"
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".yaml"))


def builtin_text(name: str) -> str:
    """The YAML text of a built-in scenario."""
    return (resources.files("gaitshift") / "scenarios" / f"{name}.yaml").read_text()


def load_scenario(name_or_path: str | Path | dict[str, Any]) -> Any:
    """Load a scenario from a built-in name, a YAML path, or a dict; validate it.

    Raises:
        ScenarioError: unknown name or file, unreadable YAML, unknown key, or a value out of range.
    """
    if isinstance(name_or_path, dict):
        data, origin = name_or_path, "<dict>"
    else:
        key = str(name_or_path)
        path = Path(key)
        if key in builtin_names():
            text, origin = builtin_text(key), key
        elif path.suffix in (".yaml", ".yml") and path.is_file():
            text, origin = path.read_text(), str(path)
        else:
            raise ScenarioError("scenario", key, "a YAML file path or one of: " + ", ".join(builtin_names()))
        try:
            data = yaml.safe_load(text)
        except yaml.YAMLError as exc:
            raise ScenarioError("scenario", origin, f"valid YAML ({str(exc).splitlines()[0]})") from None
        if not isinstance(data, dict):
            raise ScenarioError("scenario", origin, "a YAML mapping of scenario fields")
    data = dict(data)
    data.setdefault("planner", "tvlip")
    if data["planner"] not in SCHEMAS:
        raise ScenarioError("planner", data["planner"], "one of: " + ", ".join(SCHEMAS))
    if "name" not in data and origin != "<dict>":
        data["name"] = Path(origin).stem
    try:
        return _ADAPTER.validate_python(data)
    except ValidationError as exc:
        raise _scenario_error(exc, SCHEMAS[data["planner"]]) from None


def _scenario_error(exc: ValidationError, schema: type[BaseModel]) -> ScenarioError:
    err = exc.errors()[0]
    loc = [p for p in err["loc"] if p not in SCHEMAS]  # drop the discriminator tag
    field = ".".join(str(p) for p in loc) or "scenario"
    value = err.get("input")
    kind = err["type"]
    ctx = err.get("ctx", {})
    if kind == "extra_forbidden":
        model = _model_at(schema, loc[:-1])
        allowed = "known keys: " + ", ".join(model.model_fields) if model else "no such key"
        return ScenarioError(field, value, allowed + " (unknown key)")
    if kind in ("greater_than", "greater_than_equal", "less_than", "less_than_equal"):
        sym = {"greater_than": "> ", "greater_than_equal": ">= ", "less_than": "< ",
               "less_than_equal": "<= "}[kind]
        bound = next(iter(ctx.values()))
        return ScenarioError(field, value, f"{sym}{bound}")
    if kind == "finite_number" or (isinstance(value, float) and not math.isfinite(value)):
        return ScenarioError(field, value, "a finite number")
    if kind == "literal_error":
        return ScenarioError(field, value, f"one of {ctx.get('expected')}")
    msg = err["msg"].removeprefix("Value error, ")
    return ScenarioError(field, value, msg[0].lower() + msg[1:])


def _model_at(schema: type[BaseModel], loc: list[Any]) -> type[BaseModel] | None:
    model: Any = schema
    for part in loc:
        if not (isinstance(model, type) and issubclass(model, BaseModel)) or part not in model.model_fields:
            return None
        ann = model.model_fields[part].annotation
        model = next((a for a in getattr(ann, "__args__", (ann,))
                      if isinstance(a, type) and issubclass(a, BaseModel)), ann)
    return model if isinstance(model, type) and issubclass(model, BaseModel) else None
