"""The trajectory contract shared by every planner: keys, shapes, dtypes and value rules.

A :class:`Trajectory` holds arrays sampled at a fixed step ``dt``:

========================  =============  =====================================================
key                       shape          meaning
========================  =============  =====================================================
``t``                     (N,)           time, s; N >= 2, uniform step dt in [1e-6, 1] s
``com_pos``               (N, 3)         CoM position, m
``com_vel``               (N, 3)         CoM velocity, m/s
``com_acc``               (N, 3)         CoM acceleration, m/s^2
``zmp``                   (N, 3)         ZMP, m; NaN while no foot touches the ground
``phase``                 (N,) int8      0 double support, 1 single support, 2 flight
``contact``               (N, 2) bool    [left, right] foot on the ground: both in DS, one in SS,
                                         none in flight
``foot_pos``              (N, 2, 3)      sole centre of [left, right] foot, m
``stiffness``             (N,)           T of the TV-LIPM during support, s; NaN otherwise
``footsteps``             (M, 4)         x, y, z, yaw of each foothold, in order; M >= 1
``footstep_side``         (M,) int8      0 left, 1 right
``command_vel``           (N, 2)         commanded horizontal velocity; NaN where none
``meta``                  () str         JSON: ``planner``, ``gravity``, ``foot_size``, ``scenario``
========================  =============  =====================================================

Value rules: every float is finite except the NaN sentinels named above (``zmp`` and ``stiffness``
in flight, ``command_vel`` and ``command_yaw_rate`` anywhere); no value exceeds :data:`MAX_ABS` in
magnitude. ``meta`` holds
``planner`` (a name), ``gravity`` (m/s^2, > 0) and ``foot_size`` ([length, width] of the sole, m,
each in :data:`FOOT_SIZE_RANGE`), and only finite JSON numbers; a live plan's look-ahead adds
:data:`OPEN_END` (true: the run goes on past its last sample, a later plan continues it).

Planners may add keys (``extras``: numeric arrays, NaN allowed), never change these; ``boundary_t``
(phase boundary times, s), when present, is finite. Files are written atomically as ``.npz``,
``.csv`` or ``.json`` chosen by suffix (:mod:`gaitshift.trajectory.formats`) and read back by
:meth:`Trajectory.load`, which checks every rule here and names the file, the key and the value of
the first one broken (:class:`~gaitshift.errors.TrajectoryFileError`).
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import InitVar, dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.errors import TrajectoryFileError
from gaitshift.trajectory import formats

DS, SS, FLIGHT = 0, 1, 2
PHASE_NAMES = {DS: "DS", SS: "SS", FLIGHT: "F"}
LEFT, RIGHT = 0, 1
#: the ``gait`` key
STAND, WALK, RUN = 0, 1, 2
#: feet on the ground in each phase (DS, SS, FLIGHT)
FEET_DOWN = (2, 1, 0)
#: largest magnitude of any value of the contract, SI units (m, s, m/s, m/s^2)
MAX_ABS = 1e6
#: allowed sampling step, s
DT_RANGE = (1e-6, 1.0)
#: ``meta`` key of a live plan's look-ahead: true when the run goes on past its last sample
OPEN_END = "open_end"
#: allowed sole length and width in ``meta.foot_size``, m
FOOT_SIZE_RANGE = (1e-3, 10.0)


@dataclass(frozen=True)
class KeySpec:
    """One array of the contract: its key, trailing shape, dtype, NaN rule and allowed values.

    ``per`` is ``"sample"`` (leading dimension N) or ``"foothold"`` (leading dimension M). ``nan`` is
    ``"never"``, ``"flight"`` (NaN only where phase == FLIGHT) or ``"any"``.
    """

    key: str
    trailing: tuple[int, ...]
    dtype: Any
    nan: str = "never"
    values: tuple[int, ...] | None = None
    per: str = "sample"


#: every array of the contract, in validation order (``t`` and ``phase`` first: the others refer to them)
KEYS: tuple[KeySpec, ...] = (
    KeySpec("t", (), np.float64),
    KeySpec("phase", (), np.int8, values=(DS, SS, FLIGHT)),
    KeySpec("com_pos", (3,), np.float64),
    KeySpec("com_vel", (3,), np.float64),
    KeySpec("com_acc", (3,), np.float64),
    KeySpec("zmp", (3,), np.float64, nan="flight"),
    KeySpec("contact", (2,), np.bool_, values=(0, 1)),
    KeySpec("foot_pos", (2, 3), np.float64),
    KeySpec("stiffness", (), np.float64, nan="flight"),
    KeySpec("command_vel", (2,), np.float64, nan="any"),
    KeySpec("heading", (), np.float64),
    KeySpec("foot_yaw", (2,), np.float64),
    KeySpec("gait", (), np.int8, values=(0, 1, 2)),
    KeySpec("command_yaw_rate", (), np.float64, nan="any"),
    KeySpec("footsteps", (4,), np.float64, per="foothold"),
    KeySpec("footstep_side", (), np.int8, values=(LEFT, RIGHT), per="foothold"),
)
SAMPLE_KEYS = tuple(s.key for s in KEYS if s.per == "sample")
CONTRACT_KEYS = (*(s.key for s in KEYS), "meta")
#: extras with a meaning to analyses (checked like contract keys when present)
KNOWN_EXTRAS: tuple[KeySpec, ...] = (KeySpec("boundary_t", (), np.float64, per="any"),)
_EXTRA_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


@dataclass(frozen=True)
class Trajectory:
    """Sampled CoM, ZMP and foot trajectories with their footsteps (see module docstring).

    Construction checks every rule of the contract and raises
    :class:`~gaitshift.errors.TrajectoryFileError` (an ``InputError``, hence a ``ValueError``) naming
    ``source`` (the file it was read from; ``"Trajectory"`` for arrays built in memory), the key and
    the value at fault.
    """

    t: np.ndarray
    com_pos: np.ndarray
    com_vel: np.ndarray
    com_acc: np.ndarray
    zmp: np.ndarray
    phase: np.ndarray
    contact: np.ndarray
    foot_pos: np.ndarray
    stiffness: np.ndarray
    footsteps: np.ndarray
    footstep_side: np.ndarray
    command_vel: np.ndarray
    heading: np.ndarray
    foot_yaw: np.ndarray
    gait: np.ndarray
    command_yaw_rate: np.ndarray
    meta: dict[str, Any]
    extras: dict[str, np.ndarray] = field(default_factory=dict)
    source: InitVar[str] = "Trajectory"

    def __post_init__(self, source: str) -> None:
        arrays, extras = check_arrays({s.key: getattr(self, s.key) for s in KEYS}, self.extras, self.meta, source)
        for key, arr in arrays.items():
            object.__setattr__(self, key, arr)
        object.__setattr__(self, "extras", extras)

    # ----------------------------------------------------------------- convenience
    @cached_property
    def dt(self) -> float:
        """Sampling step, s: ``meta["dt"]`` where the planner wrote it (exact, also for a window far into a
        run, :mod:`gaitshift.trajectory.window`), else ``t[1] - t[0]``; read once (a trajectory is frozen)."""
        step, first = self.meta.get("dt"), float(self.t[1] - self.t[0])
        if isinstance(step, float | int) and not isinstance(step, bool) and abs(step - first) <= 1e-6 * first:
            return float(step)
        return first

    @property
    def gravity(self) -> float:
        """Gravity magnitude used by the planner, m/s^2."""
        return float(self.meta["gravity"])

    def __len__(self) -> int:
        return len(self.t)

    def arrays(self) -> dict[str, np.ndarray]:
        """All arrays of the contract plus the extras, keyed as in the file."""
        out = {k: getattr(self, k) for k in SAMPLE_KEYS}
        out["footsteps"] = self.footsteps
        out["footstep_side"] = self.footstep_side
        out.update(self.extras)
        return out

    # ----------------------------------------------------------------- persistence
    def save(self, path: str | Path) -> Path:
        """Write the trajectory to ``path`` (.npz, .csv or .json by suffix), atomically."""
        return formats.write(path, self.arrays(), self.meta, len(self))

    @classmethod
    def load(cls, path: str | Path) -> Trajectory:
        """Read a file written by :meth:`save`, checking every rule of the contract.

        Raises:
            TrajectoryFileError: the file is missing, unreadable, not of its suffix's format, or
                breaks the contract; the message names the file, the key and the value.
        """
        data, meta = formats.read(path)
        return cls.from_arrays(data, meta, source=str(path))

    @classmethod
    def from_arrays(cls, data: dict[str, np.ndarray], meta: Any, source: str = "Trajectory") -> Trajectory:
        """Build from a dict of arrays keyed as in the file; unknown keys become extras.

        ``source`` names where the arrays came from in error messages.
        """
        for spec in KEYS:
            if spec.key not in data:
                raise TrajectoryFileError(source, spec.key, "missing", "every key of " + ", ".join(CONTRACT_KEYS))
        core = {s.key: data[s.key] for s in KEYS}
        extras = {k: v for k, v in data.items() if k not in core}
        return cls(**core, meta=meta, extras=extras, source=source)


def standing_samples(phase: np.ndarray) -> np.ndarray:
    """(N,) bool: the double-support samples before the first and after the last non-DS sample (the
    robot standing before it starts and after it stops)."""
    moving = np.flatnonzero(np.asarray(phase) != DS)
    out = np.ones(len(phase), dtype=bool)
    if len(moving):
        out[moving[0] : moving[-1] + 1] = False
    return out


# ====================================================================== the rules
def check_arrays(
    arrays: dict[str, Any], extras: dict[str, Any], meta: Any, source: str
) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """The contract arrays cast to their dtypes, and the extras, after checking every rule.

    Raises:
        TrajectoryFileError: the first rule broken, naming ``source``, the key and what was found.
    """
    check_meta(meta, source)
    t = _numeric(arrays["t"], source, "t")
    if t.ndim != 1 or len(t) < 2:
        raise TrajectoryFileError(source, "t", f"shape {t.shape}", "shape (N,) with N >= 2 samples")
    steps = _numeric(arrays["footsteps"], source, "footsteps")
    if steps.size == 0:
        raise TrajectoryFileError(source, "footsteps", "no foothold", "at least one foothold (M >= 1)")
    lead = {"sample": len(t), "foothold": len(steps) if steps.ndim else 0}
    out: dict[str, np.ndarray] = {}
    for spec in KEYS:
        phase = out.get("phase") if spec.per == "sample" else None
        out[spec.key] = _check_key(spec, arrays[spec.key], lead[spec.per], phase, source)
    _check_time(out["t"], source)
    _check_contact(out["phase"], out["contact"], source)
    return out, _check_extras(extras, source)


def _check_key(spec: KeySpec, value: Any, lead: int, phase: np.ndarray | None, source: str) -> np.ndarray:
    arr = _numeric(value, source, spec.key)
    want = (lead, *spec.trailing)
    if arr.shape != want:
        dims = "N = len(t)" if spec.per == "sample" else "M = number of footholds"
        raise TrajectoryFileError(source, spec.key, f"shape {arr.shape}", f"shape {want} ({dims})")
    if spec.values is not None:
        bad = ~np.isin(arr, spec.values)
        if bad.any():
            i = int(np.flatnonzero(bad.reshape(len(arr), -1).any(axis=1))[0])
            found = f"{_show(arr[i])} at index {i}"
            raise TrajectoryFileError(source, spec.key, found, "values in {" + ", ".join(map(str, spec.values)) + "}")
        return arr.astype(spec.dtype)
    arr = arr.astype(np.float64)
    _check_floats(spec, arr, phase, source)
    return arr


def _check_floats(spec: KeySpec, arr: np.ndarray, phase: np.ndarray | None, source: str) -> None:
    """Finite (or NaN where ``spec.nan`` allows it) and within :data:`MAX_ABS`."""
    if arr.size == 0:
        return
    flat = arr.reshape(len(arr), -1)
    with np.errstate(invalid="ignore"):
        bad = ~(np.abs(flat) <= MAX_ABS)  # NaN and inf are bad here
    nan = np.isnan(flat)
    if spec.nan == "any":
        bad &= ~nan
    elif spec.nan == "flight" and phase is not None:
        bad &= ~(nan & (phase == FLIGHT)[:, None])
    if not bad.any():
        return
    i = int(np.flatnonzero(bad.any(axis=1))[0])
    allowed = {
        "never": f"finite numbers within +/-{MAX_ABS:g}",
        "flight": f"finite numbers within +/-{MAX_ABS:g}; NaN only in flight (phase {FLIGHT})",
        "any": f"numbers within +/-{MAX_ABS:g} or NaN",
    }[spec.nan]
    where = f" (phase {PHASE_NAMES[int(phase[i])]})" if phase is not None else ""
    raise TrajectoryFileError(source, spec.key, f"{_show(arr[i])} at index {i}{where}", allowed)


def _check_time(t: np.ndarray, source: str) -> None:
    dt = float(t[1] - t[0])
    lo, hi = DT_RANGE
    if not lo <= dt <= hi:
        raise TrajectoryFileError(source, "t", f"step t[1] - t[0] = {dt:g} s", f"a step dt in [{lo:g}, {hi:g}] s")
    off = np.abs(np.diff(t) - dt) > 1e-6 * dt
    if off.any():
        i = int(np.flatnonzero(off)[0])
        step = float(t[i + 1] - t[i])
        raise TrajectoryFileError(source, "t", f"step {step:.9g} s at index {i}", f"a uniform step dt = {dt:g} s")


def _check_contact(phase: np.ndarray, contact: np.ndarray, source: str) -> None:
    down = contact.sum(axis=1)
    bad = down != np.asarray(FEET_DOWN)[phase]
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        found = f"{contact[i].tolist()} at index {i} in phase {PHASE_NAMES[int(phase[i])]}"
        raise TrajectoryFileError(source, "contact", found, "both feet in DS, one in SS, none in flight")


def _check_extras(extras: Any, source: str) -> dict[str, np.ndarray]:
    if not isinstance(extras, dict):
        raise TrajectoryFileError(source, "extras", type(extras).__name__, "a dict of arrays")
    known = {s.key: s for s in KNOWN_EXTRAS}
    out = {}
    for key, value in extras.items():
        if not isinstance(key, str) or not _EXTRA_NAME.fullmatch(key) or key in CONTRACT_KEYS:
            found = repr(key)[:80]
            raise TrajectoryFileError(source, "extra key", found, "a name [A-Za-z_][A-Za-z0-9_]* not in the contract")
        arr = _numeric(value, source, key)
        spec = known.get(key)
        if spec is not None:
            if arr.ndim != 1:
                raise TrajectoryFileError(source, key, f"shape {arr.shape}", "shape (K,)")
            _check_floats(spec, arr.astype(np.float64), None, source)
        elif arr.dtype.kind == "f" and np.isinf(arr).any():
            i = int(np.flatnonzero(np.isinf(arr).reshape(-1))[0])
            raise TrajectoryFileError(source, key, f"inf at flat index {i}", "numbers or NaN")
        out[key] = arr
    return out


def check_meta(meta: Any, source: str) -> None:
    """``meta`` is a JSON object with ``planner``, ``gravity`` and ``foot_size`` (see module docstring)
    and finite numbers only."""
    if not isinstance(meta, dict):
        raise TrajectoryFileError(source, "meta", f"a {type(meta).__name__}", "a JSON object")
    for key, ok, allowed in (
        ("planner", isinstance(meta.get("planner"), str) and meta.get("planner") != "", "a planner name (string)"),
        ("gravity", _number_in(meta.get("gravity"), 1e-3, MAX_ABS), "a number in [0.001, 1e6] m/s^2"),
        (
            "foot_size",
            isinstance(meta.get("foot_size"), list | tuple)
            and len(meta["foot_size"]) == 2
            and all(_number_in(x, *FOOT_SIZE_RANGE) for x in meta["foot_size"]),
            "[length, width] of the sole, each in [{:g}, {:g}] m".format(*FOOT_SIZE_RANGE),
        ),
    ):
        if key not in meta:
            raise TrajectoryFileError(source, f"meta.{key}", "missing", allowed)
        if not ok:
            raise TrajectoryFileError(source, f"meta.{key}", _show(meta[key]), allowed)
    where = _not_json(meta, "meta")
    if where is not None:
        raise TrajectoryFileError(source, where[0], where[1], "JSON values with finite numbers")


def _not_json(value: Any, path: str) -> tuple[str, str] | None:
    """(dotted path, value) of the first entry of ``value`` that is not finite JSON, or None."""
    if isinstance(value, dict):
        for k, v in value.items():
            if not isinstance(k, str):
                return path, f"the key {k!r}"
            bad = _not_json(v, f"{path}.{k}")
            if bad is not None:
                return bad
        return None
    if isinstance(value, list | tuple):
        return next((b for i, v in enumerate(value) if (b := _not_json(v, f"{path}.{i}")) is not None), None)
    if isinstance(value, float) and not math.isfinite(value):
        return path, repr(value)
    if value is None or isinstance(value, str | int | float):
        return None
    return path, f"a {type(value).__name__}"


def _number_in(x: Any, lo: float, hi: float) -> bool:
    return isinstance(x, int | float) and not isinstance(x, bool) and lo <= x <= hi


def _numeric(value: Any, source: str, key: str) -> np.ndarray:
    """``value`` as an array of numbers (bool, int or float dtype)."""
    try:
        arr = np.asarray(value)
    except (ValueError, TypeError) as exc:
        raise TrajectoryFileError(source, key, str(exc).splitlines()[0][:80], "an array of numbers") from None
    if arr.dtype.kind not in formats.NUMERIC_KINDS:
        raise TrajectoryFileError(source, key, f"dtype {arr.dtype}", "an array of numbers (bool, int or float)")
    return arr


def _show(value: Any) -> str:
    """``value`` as short JSON-like text for a message (arrays and numpy scalars as plain numbers)."""
    if isinstance(value, np.ndarray | np.generic):
        value = value.tolist()
    text = json.dumps(value, default=repr)
    return text if len(text) <= 80 else text[:77] + "..."
