"""The campaign spec (YAML, validated with pydantic): a task and the axes it sweeps.

Example::

    name: g1-push-map
    task: simulate            # simulate | plan | reference
    duration: 2.5             # locomotion scenarios: stop_at, s (optional)
    axes:
      scenario: [walk.yaml]                       # a list
      speed: {start: 0.3, stop: 0.9, step: 0.15}  # a range, stop included
      push_impulse: {low: 0, high: 40, n: 8, seed: 1}   # a random sample (uniform)
      mass_scale: [0.9, 1.0, 1.2]

With ``sample: {cases: N, seed: S}`` the cases are not the product of the axes but ``N`` random
draws: each case takes, per axis, a uniform draw from its interval ``{low, high}`` (integers for
integer axes) or a uniform choice from its list or range (:mod:`gaitshift.campaign.sampling`)::

    sample: {cases: 2000, seed: 0}
    axes:
      speed: {low: 0.0, high: 2.0}
      noise: [typical, rl-peer]

The axis names are those of :data:`gaitshift.campaign.axes.AXES`. ``reference`` (task ``reference``)
chooses the motion written per case: ``closed-loop`` (the simulated robot, physically consistent) or
``kinematic`` (the plan's whole-body IK), at ``rate`` Hz. Every error is one
:class:`~gaitshift.errors.InputError` naming the dotted field (``axes.speed.step``).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import Field, Strict, ValidationError, model_validator

from gaitshift.campaign.axes import AXES, check_exclusive, check_simulated, check_value
from gaitshift.errors import InputError
from gaitshift.scenario.fields import StrictModel, input_error
from gaitshift.scenario.loader import yaml_mapping, yaml_text

__all__ = [
    "CampaignSpec",
    "RangeAxis",
    "ReferenceSettings",
    "SampleAxis",
    "SampleSettings",
    "axis_list",
    "is_interval",
    "load_spec",
]

Num = Annotated[float, Strict(), Field(allow_inf_nan=False)]
#: at most this many values on one axis
MAX_AXIS_VALUES = 100_000


class RangeAxis(StrictModel):
    """``start, start + step, ...`` up to ``stop`` included (within step/1e6); step > 0, stop >= start."""

    start: Num
    stop: Num
    step: Num

    @model_validator(mode="after")
    def _not_empty(self) -> RangeAxis:
        if not self.step > 0:
            raise ValueError(f"a step > 0 (got step = {self.step}: an empty range)")
        if self.stop < self.start:
            raise ValueError(f"stop >= start (got {self.start} .. {self.stop}: an empty range)")
        if (self.stop - self.start) / self.step > MAX_AXIS_VALUES:
            raise ValueError(f"at most {MAX_AXIS_VALUES} values")
        return self

    def values(self) -> list[float]:
        """The values of the range, rounded to 12 significant digits (0.1 + 0.2 -> 0.3)."""
        n = math.floor((self.stop - self.start) / self.step + 1e-6) + 1
        return [float(f"{self.start + i * self.step:.12g}") for i in range(n)]


class SampleAxis(StrictModel):
    """``n`` values drawn uniformly in [low, high] with ``seed`` (numpy's default generator)."""

    low: Num
    high: Num
    n: Annotated[int, Strict(), Field(ge=1, le=MAX_AXIS_VALUES)]
    seed: Annotated[int, Strict(), Field(ge=0)] = 0

    @model_validator(mode="after")
    def _ordered(self) -> SampleAxis:
        if self.high < self.low:
            raise ValueError(f"high >= low (got {self.low} .. {self.high}: an empty interval)")
        return self

    def values(self) -> list[float]:
        """The sample, in draw order."""
        rng = np.random.default_rng(self.seed)
        return [float(v) for v in rng.uniform(self.low, self.high, self.n)]


def is_interval(given: Any) -> bool:
    """True when an axis is given as an interval ``{low, high}`` (a sample spec's per-case draw)."""
    return isinstance(given, dict) and set(given) == {"low", "high"}


def axis_list(name: str, given: Any) -> list[Any]:
    """The raw values of axis ``name`` as the spec gives them: a list, a range mapping (start, stop,
    step) or a sample mapping (low, high, n, seed).

    Raises:
        InputError: naming ``axes.<name>`` (or its key), the value and what is allowed.
    """
    field = f"axes.{name}"
    if isinstance(given, list):
        return given
    if not isinstance(given, dict):
        raise InputError(field, given, "a list, a range {start, stop, step} or a sample {low, high, n, seed}")
    schema: type[StrictModel] = RangeAxis if "step" in given or "start" in given else SampleAxis
    try:
        return schema.model_validate(given).values()  # type: ignore[attr-defined, no-any-return]
    except ValidationError as exc:
        raise input_error(exc, schema, InputError, prefix=field + ".") from None


class ReferenceSettings(StrictModel):
    """Task ``reference``: the motion written per case and its sample rate, Hz."""

    mode: Literal["closed-loop", "kinematic"] = "closed-loop"
    rate: Annotated[float, Strict(), Field(gt=0, le=1000, allow_inf_nan=False)] = 50.0


#: the most cases a campaign may expand to (a spec beyond it is refused before anything is built)
MAX_CASES = 1_000_000


class SampleSettings(StrictModel):
    """Random sampling instead of the product: ``cases`` draws with ``seed`` (module docstring)."""

    cases: Annotated[int, Strict(), Field(ge=1, le=MAX_CASES)]
    seed: Annotated[int, Strict(), Field(ge=0, le=2**32 - 1)] = 0


class CampaignSpec(StrictModel):
    """A campaign (module docstring). ``base`` is the folder relative scenario paths are read from."""

    name: str = "campaign"
    description: str = ""
    task: Literal["simulate", "plan", "reference"]
    axes: dict[str, Any] = Field(default_factory=dict)
    duration: Annotated[float, Strict(), Field(gt=0, le=3600, allow_inf_nan=False)] | None = None
    control_period: Annotated[float, Strict(), Field(ge=5e-4, le=0.01, allow_inf_nan=False)] = 0.002
    reference: ReferenceSettings = ReferenceSettings()
    sample: SampleSettings | None = None
    base: str = "."

    def axis_values(self) -> dict[str, list[Any]]:
        """Every axis (registry order) -> its checked values; axes not in the spec: [default]; an
        interval of a sample spec: its two ends.

        Raises:
            InputError: an unknown axis, an empty list, a value outside its axis's range, or a
                ``terrain`` in a spec that does not simulate.
        """
        unknown = [k for k in self.axes if k not in AXES]
        if unknown:
            raise InputError(f"axes.{unknown[0]}", "(unknown axis)", "axes: " + ", ".join(AXES))
        out: dict[str, list[Any]] = {}
        for name in AXES:
            given = self.axes.get(name)
            if given is None:
                out[name] = [AXES[name].default]
                continue
            raw = self._interval(name, given) if is_interval(given) else axis_list(name, given)
            if not raw:
                raise InputError(f"axes.{name}", [], "a non-empty list of values (an empty axis has no case)")
            vals = [check_value(name, f"axes.{name}[{i}]", v) for i, v in enumerate(raw)]
            out[name] = list(dict.fromkeys(vals))  # duplicates would be the same case
        check_exclusive(out)
        check_simulated(self.simulates, out)
        return out

    @property
    def simulates(self) -> bool:
        """Whether a case runs closed loop (task ``simulate``, a ``closed-loop`` reference)."""
        return self.task == "simulate" or (self.task == "reference" and self.reference.mode == "closed-loop")

    def _interval(self, name: str, given: dict[str, Any]) -> list[Any]:
        """The ends [low, high] of an interval axis (sample specs only, numeric axes only)."""
        field = f"axes.{name}"
        if self.sample is None:
            raise InputError(field, given, "a list, a range {start, stop, step} or a sample {low, high, n, seed}")
        if AXES[name].kind == "str":
            raise InputError(field, given, "a list of values (a text axis has no interval)")
        low, high = given["low"], given["high"]
        if isinstance(low, int | float) and isinstance(high, int | float) and high < low:
            raise InputError(f"{field}.high", high, f"a number >= low ({low})")
        return [low, high]

    def scenario_path(self, scenario: str) -> str:
        """A scenario value as given to the loader: a YAML path relative to ``base``, or a name."""
        p = Path(scenario)
        if p.suffix.lower() in (".yaml", ".yml") and not p.is_absolute():
            return str(Path(self.base) / p)
        return scenario


def load_spec(source: str | Path | dict[str, Any]) -> CampaignSpec:
    """Read and validate a spec from a YAML path or a mapping; its axes are checked too.

    Raises:
        InputError: missing or bad YAML, unknown key or axis, empty range, a value out of range.
    """
    if isinstance(source, dict):
        data, base = dict(source), str(source.get("base", "."))
    else:
        path = Path(source)
        text = yaml_text(path, "spec", "a campaign spec YAML file", InputError)
        data, base = yaml_mapping(text, "spec", str(path), "campaign keys", InputError), str(path.parent)
    data.setdefault("base", base)
    try:
        spec = CampaignSpec.model_validate(data)
    except ValidationError as exc:
        raise input_error(exc, CampaignSpec, InputError) from None
    spec.axis_values()
    return spec
