"""Shared pieces of the scenario schemas: the strict base model, bounded number types, the foot, and
the conversion of a pydantic validation error into one :class:`~gaitshift.errors.InputError`.

Numbers are strict: an int is accepted where a float is expected, a bool or a string is not, and
NaN or inf never. Every number has a physical range (SI units), wide enough for any humanoid and
narrow enough that the planners' arithmetic stays finite.
"""

from __future__ import annotations

import reprlib
from collections.abc import Iterable
from typing import Annotated, Any

from pydantic import BaseModel, ConfigDict, Field, Strict, ValidationError, model_validator

from gaitshift.errors import InputError

#: largest number of samples a scenario may ask for (plan duration / dt): ~33 min at 1 ms
MAX_SAMPLES = 2_000_000

#: physical ranges shared with the CLI flags that take the same quantities (low, high)
COM_HEIGHT_RANGE = (0.05, 5.0)  # m, CoM height above the ground (inclusive)
GRAVITY_RANGE = (0.1, 100.0)  # m/s^2 (inclusive): the Moon 1.62, the Earth 9.81, Jupiter 24.8
DURATION_RANGE = (1e-3, 2.0)  # s, one phase or step (inclusive)

#: any finite number within +/- 1e6 (coordinates, yaw)
Real = Annotated[float, Strict(), Field(ge=-1e6, le=1e6, allow_inf_nan=False)]
#: a duration of one phase or step, s
Duration = Annotated[float, Strict(), Field(ge=DURATION_RANGE[0], le=DURATION_RANGE[1], allow_inf_nan=False)]
#: a standing phase (start, stop), s
StandDuration = Annotated[float, Strict(), Field(gt=0, le=10, allow_inf_nan=False)]
#: a positive length (stride, step width, sole side), m
Length = Annotated[float, Strict(), Field(gt=0, le=10, allow_inf_nan=False)]
#: a length that may be 0 (margin, clearance, rise), m
NonNegLength = Annotated[float, Strict(), Field(ge=0, le=10, allow_inf_nan=False)]
#: a signed length (vertical offsets, rises), m
SignedLength = Annotated[float, Strict(), Field(ge=-10, le=10, allow_inf_nan=False)]
#: CoM height above the ground, m
ComHeight = Annotated[float, Strict(), Field(ge=COM_HEIGHT_RANGE[0], le=COM_HEIGHT_RANGE[1], allow_inf_nan=False)]
#: gravity magnitude, m/s^2
Gravity = Annotated[float, Strict(), Field(ge=GRAVITY_RANGE[0], le=GRAVITY_RANGE[1], allow_inf_nan=False)]
#: a signed speed, m/s
Speed = Annotated[float, Strict(), Field(ge=-20, le=20, allow_inf_nan=False)]
#: a positive speed or speed change, m/s
PosSpeed = Annotated[float, Strict(), Field(gt=0, le=20, allow_inf_nan=False)]
#: a vertical acceleration, m/s^2
Accel = Annotated[float, Strict(), Field(ge=-1000, le=1000, allow_inf_nan=False)]
#: one side of a sole rectangle, m
SoleSide = Annotated[float, Strict(), Field(ge=0.01, le=2, allow_inf_nan=False)]
#: a count of steps
Count = Annotated[int, Strict(), Field(ge=0, le=100_000)]


class StrictModel(BaseModel):
    """Base of every scenario part: unknown keys are errors, instances are immutable."""

    model_config = ConfigDict(extra="forbid", frozen=True)


class Foot(StrictModel):
    """Sole rectangle [length, width] in m, and the margin by which the ZMP box of eq. (7) of 001 is
    shrunk inside it. ``zmp_z`` is the allowed vertical offset of the 3D ZMP from the sole plane."""

    size: tuple[SoleSide, SoleSide] = (0.22, 0.12)
    zmp_margin: NonNegLength = 0.01
    zmp_z: tuple[SignedLength, SignedLength] = (0.0, 0.0)

    @model_validator(mode="after")
    def _margin_fits(self) -> Foot:
        if 2 * self.zmp_margin >= min(self.size):
            raise ValueError(f"zmp_margin={self.zmp_margin} leaves no ZMP area in a sole of {list(self.size)}")
        if self.zmp_z[0] > self.zmp_z[1]:
            raise ValueError(f"zmp_z lower bound {self.zmp_z[0]} exceeds upper bound {self.zmp_z[1]}")
        return self


def check_samples(duration: float, dt: float) -> None:
    """Raise ``ValueError`` (a schema error on the model) when ``duration / dt`` exceeds MAX_SAMPLES."""
    if duration / dt > MAX_SAMPLES:
        raise ValueError(
            f"a plan of at most {MAX_SAMPLES} samples (this one lasts about {duration:.4g} s at dt = {dt:g} s, "
            f"{duration / dt:.3g} samples): fewer steps or a larger dt"
        )


# ====================================================================== pydantic error -> InputError
class Missing:
    """Stands for the value of a required key that is absent (prints as ``missing``)."""

    def __repr__(self) -> str:
        return "missing"


class Shown(str):
    """Text shown as is in an error message (no quotes), e.g. a clipped long value."""

    def __repr__(self) -> str:
        return str(self)


_BOUNDS = {"greater_than": "> ", "greater_than_equal": ">= ", "less_than": "< ", "less_than_equal": "<= "}


def input_error(
    exc: ValidationError, schema: type[BaseModel], error: type[InputError] = InputError, prefix: str = ""
) -> InputError:
    """The first error of ``exc`` as one ``error(field, value, allowed)``: ``field`` is the dotted
    path (``prefix`` + ``timing.flight``), ``value`` what was given there and ``allowed`` the rule."""
    err = exc.errors()[0]
    loc = list(err["loc"])
    kind, ctx, value = err["type"], err.get("ctx", {}), err.get("input")
    if kind == "missing" and loc and isinstance(loc[-1], int):  # a fixed-length list with too few items
        index, loc = loc[-1], loc[:-1]
        return error(prefix + ".".join(map(str, loc)), _short(value), f"more items (item {index} is missing)")
    if kind == "missing":
        value = Missing()
    dotted = ".".join(str(p) for p in loc)
    field = prefix + dotted if dotted else (prefix.rstrip(".") or "scenario")
    if kind == "extra_forbidden":
        model = model_at(schema, loc[:-1])
        allowed = "known keys: " + ", ".join(model.model_fields) if model else "no such key"
        return error(field, _short(value), allowed + " (unknown key)")
    if kind in _BOUNDS:
        return error(field, value, f"{_BOUNDS[kind]}{next(iter(ctx.values()))}")
    if kind == "finite_number":
        return error(field, value, "a finite number")
    if kind == "literal_error":
        return error(field, _short(value), f"one of {ctx.get('expected')}")
    if kind == "missing":
        return error(field, value, "a value (required key)")
    if kind in ("model_type", "dict_type", "model_attributes_type"):
        return error(field, _short(value), "a mapping of keys to values")
    msg = str(err["msg"]).removeprefix("Value error, ")
    return error(field, _short(value), msg[0].lower() + msg[1:])


def model_at(schema: type[BaseModel], loc: Iterable[Any]) -> type[BaseModel] | None:
    """The model class reached from ``schema`` along the field path ``loc`` (None if it is not one)."""
    model: Any = schema
    for part in loc:
        if isinstance(part, int):  # an item of a tuple of models: same model
            continue
        if not (isinstance(model, type) and issubclass(model, BaseModel)) or part not in model.model_fields:
            return None
        ann = model.model_fields[part].annotation
        model = _model_in(ann)
    return model if isinstance(model, type) and issubclass(model, BaseModel) else None


def _model_in(ann: Any) -> Any:
    """The BaseModel class inside an annotation (``X``, ``X | None``, ``tuple[X, ...]``), else ``ann``."""
    if isinstance(ann, type) and issubclass(ann, BaseModel):
        return ann
    for arg in getattr(ann, "__args__", ()):
        found = _model_in(arg)
        if isinstance(found, type) and issubclass(found, BaseModel):
            return found
    return ann


_REPR = reprlib.Repr()
_REPR.maxlevel, _REPR.maxtuple, _REPR.maxlist, _REPR.maxdict, _REPR.maxset = 3, 4, 4, 4, 4
_REPR.maxstring, _REPR.maxlong, _REPR.maxother = 60, 40, 60


def short_repr(value: Any, limit: int = 80) -> Shown:
    """A short one-line repr of ``value`` (bounded in depth and length even for huge nested inputs)."""
    text = _REPR.repr(value).replace("\n", " ").replace("\r", " ")
    return Shown(text if len(text) <= limit else text[: limit - 3] + "...")


def _short(value: Any) -> Any:
    """``value`` itself when it is a plain number, else its :func:`short_repr`."""
    return value if isinstance(value, int | float) and not isinstance(value, bool) else short_repr(value)


def one_line(exc: BaseException, limit: int = 100) -> str:
    """The first line of an exception's message, shortened to ``limit`` characters."""
    lines = str(exc).strip().splitlines()
    text = lines[0] if lines else type(exc).__name__
    return text if len(text) <= limit else text[: limit - 3] + "..."
