"""The trajectory file contract shared by every planner.

A :class:`Trajectory` holds arrays sampled at a fixed step ``dt``:

========================  =============  =====================================================
key                       shape          meaning
========================  =============  =====================================================
``t``                     (N,)           time, s
``com_pos``               (N, 3)         CoM position, m
``com_vel``               (N, 3)         CoM velocity, m/s
``com_acc``               (N, 3)         CoM acceleration, m/s^2
``zmp``                   (N, 3)         ZMP, m; NaN while no foot touches the ground
``phase``                 (N,) int8      0 double support, 1 single support, 2 flight
``contact``               (N, 2) bool    [left, right] foot on the ground
``foot_pos``              (N, 2, 3)      sole centre of [left, right] foot, m
``stiffness``             (N,)           T of the TV-LIPM during support, s; NaN otherwise
``footsteps``             (M, 4)         x, y, z, yaw of each foothold, in order
``footstep_side``         (M,) int8      0 left, 1 right
``command_vel``           (N, 2)         commanded horizontal velocity; NaN where none
``meta``                  () str         JSON: ``planner``, ``gravity``, ``foot_size``, ``scenario``
========================  =============  =====================================================

Planners may add keys (``extras``), never change these. Files are written atomically as ``.npz``,
``.csv`` or ``.json`` chosen by suffix, and read back by :meth:`Trajectory.load`.
"""

from __future__ import annotations

import csv
import io as _io
import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .errors import InputError
from .io import atomic_path

DS, SS, FLIGHT = 0, 1, 2
PHASE_NAMES = {DS: "DS", SS: "SS", FLIGHT: "F"}
LEFT, RIGHT = 0, 1

#: (key, trailing shape, dtype) of every per-sample array of the contract.
SAMPLE_KEYS: tuple[tuple[str, tuple[int, ...], Any], ...] = (
    ("t", (), np.float64),
    ("com_pos", (3,), np.float64),
    ("com_vel", (3,), np.float64),
    ("com_acc", (3,), np.float64),
    ("zmp", (3,), np.float64),
    ("phase", (), np.int8),
    ("contact", (2,), np.bool_),
    ("foot_pos", (2, 3), np.float64),
    ("stiffness", (), np.float64),
    ("command_vel", (2,), np.float64),
)
CONTRACT_KEYS = tuple(k for k, _, _ in SAMPLE_KEYS) + ("footsteps", "footstep_side", "meta")
SUFFIXES = (".npz", ".csv", ".json")


def check_suffix(path: str | Path, field: str) -> str:
    """The lower-case suffix of ``path``; raise :class:`InputError` naming ``field`` unless it is one
    of :data:`SUFFIXES`."""
    suffix = Path(path).suffix.lower()
    if suffix not in SUFFIXES:
        raise InputError(field, str(path), "a file ending in " + ", ".join(SUFFIXES))
    return suffix


@dataclass(frozen=True)
class Trajectory:
    """Sampled CoM, ZMP and foot trajectories with their footsteps (see module docstring)."""

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
    meta: dict[str, Any]
    extras: dict[str, np.ndarray] = field(default_factory=dict)

    def __post_init__(self) -> None:
        n = len(self.t)
        for key, trailing, dtype in SAMPLE_KEYS:
            arr = np.asarray(getattr(self, key), dtype=dtype)
            if arr.shape != (n, *trailing):
                raise ValueError(f"Trajectory.{key} has shape {arr.shape}, expected {(n, *trailing)}")
            object.__setattr__(self, key, arr)
        fs = np.asarray(self.footsteps, dtype=np.float64).reshape(-1, 4)
        side = np.asarray(self.footstep_side, dtype=np.int8).reshape(-1)
        if len(side) != len(fs):
            raise ValueError("footsteps and footstep_side differ in length")
        object.__setattr__(self, "footsteps", fs)
        object.__setattr__(self, "footstep_side", side)
        for key in ("com_pos", "com_vel", "com_acc", "foot_pos", "t", "footsteps"):
            if not np.all(np.isfinite(getattr(self, key))):
                raise ValueError(f"Trajectory.{key} contains NaN or inf")
        for key in ("planner", "gravity", "foot_size"):
            if key not in self.meta:
                raise ValueError(f"Trajectory.meta lacks {key!r}")

    # ----------------------------------------------------------------- convenience
    @property
    def dt(self) -> float:
        """Sampling step, s."""
        return float(self.t[1] - self.t[0]) if len(self.t) > 1 else 0.0

    @property
    def gravity(self) -> float:
        """Gravity magnitude used by the planner, m/s^2."""
        return float(self.meta["gravity"])

    def __len__(self) -> int:
        return len(self.t)

    def arrays(self) -> dict[str, np.ndarray]:
        """All arrays of the contract plus the extras, keyed as in the file."""
        out = {k: getattr(self, k) for k, _, _ in SAMPLE_KEYS}
        out["footsteps"] = self.footsteps
        out["footstep_side"] = self.footstep_side
        out.update(self.extras)
        return out

    # ----------------------------------------------------------------- persistence
    def save(self, path: str | Path) -> Path:
        """Write the trajectory to ``path`` (.npz, .csv or .json by suffix), atomically."""
        path = Path(path)
        suffix = check_suffix(path, "out")
        with atomic_path(path) as tmp:
            if suffix == ".npz":
                np.savez_compressed(tmp, **self.arrays(), meta=np.array(json.dumps(self.meta)))
            elif suffix == ".json":
                tmp.write_text(json.dumps(self._json_dict(), allow_nan=False))
            else:
                tmp.write_text(self._csv_text())
        return path

    @classmethod
    def load(cls, path: str | Path) -> "Trajectory":
        """Read a file written by :meth:`save`."""
        path = Path(path)
        suffix = check_suffix(path, "file")
        if not path.is_file():
            raise InputError("file", str(path), "an existing trajectory file")
        if suffix == ".npz":
            with np.load(path, allow_pickle=False) as z:
                data = {k: z[k] for k in z.files}
            meta = json.loads(str(data.pop("meta")))
        elif suffix == ".json":
            raw = json.loads(path.read_text())
            meta = raw.pop("meta")
            data = {k: np.array(_nan_from_null(v), dtype=float) for k, v in raw.items()}
        else:
            data, meta = _read_csv(path.read_text())
        return cls.from_arrays(data, meta)

    @classmethod
    def from_arrays(cls, data: dict[str, np.ndarray], meta: dict[str, Any]) -> "Trajectory":
        """Build from a dict of arrays keyed as in the file; unknown keys become extras."""
        missing = [k for k in CONTRACT_KEYS if k != "meta" and k not in data]
        if missing:
            raise InputError("file", f"missing keys {missing}", "a trajectory with every contract key")
        core = {k: data[k] for k in CONTRACT_KEYS if k != "meta"}
        extras = {k: np.asarray(v) for k, v in data.items() if k not in core}
        return cls(**core, meta=meta, extras=extras)

    def _json_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {k: _null_from_nan(np.asarray(v)) for k, v in self.arrays().items()}
        out["meta"] = self.meta
        return out

    def _csv_text(self) -> str:
        buf = _io.StringIO()
        buf.write("# meta: " + json.dumps(self.meta) + "\n")
        buf.write("# footsteps: " + json.dumps(self.footsteps.tolist()) + "\n")
        buf.write("# footstep_side: " + json.dumps(self.footstep_side.tolist()) + "\n")
        cols, blocks, shapes = [], [], {}
        for key, arr in self.arrays().items():
            if key in ("footsteps", "footstep_side") or len(arr) != len(self.t):
                continue
            flat = np.asarray(arr, dtype=float).reshape(len(self.t), -1)
            names = [key] if flat.shape[1] == 1 and arr.ndim == 1 else [
                f"{key}[{'.'.join(map(str, idx))}]" for idx in np.ndindex(*arr.shape[1:])]
            cols += names
            blocks.append(flat)
            shapes[key] = list(arr.shape[1:])
        buf.write("# shapes: " + json.dumps(shapes) + "\n")
        buf.write(",".join(cols) + "\n")
        body = _io.StringIO()
        np.savetxt(body, np.hstack(blocks), fmt="%.17g", delimiter=",")
        buf.write(body.getvalue().replace("nan", ""))  # numeric block only: NaN -> empty cell
        return buf.getvalue()


def _null_from_nan(arr: np.ndarray) -> Any:
    if arr.dtype.kind == "f":
        obj = arr.astype(object)
        obj[~np.isfinite(arr)] = None
        return obj.tolist()
    return arr.tolist()


def _nan_from_null(v: Any) -> Any:
    if isinstance(v, list):
        return [_nan_from_null(x) for x in v]
    return math.nan if v is None else v


def _read_csv(text: str) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
    header: dict[str, Any] = {}
    lines = text.splitlines()
    body_start = 0
    for i, line in enumerate(lines):
        if not line.startswith("# "):
            body_start = i
            break
        key, _, value = line[2:].partition(": ")
        header[key] = json.loads(value)
    rows = list(csv.reader(lines[body_start:]))
    cols = rows[0]
    values = np.array([[float(x) if x != "" else math.nan for x in r] for r in rows[1:]], dtype=float)
    data: dict[str, np.ndarray] = {}
    pos = 0
    for key, trailing in header["shapes"].items():
        width = int(np.prod(trailing)) if trailing else 1
        assert cols[pos].startswith(key)
        data[key] = values[:, pos:pos + width].reshape(len(values), *trailing)
        pos += width
    data["footsteps"] = np.array(header["footsteps"], dtype=float).reshape(-1, 4)
    data["footstep_side"] = np.array(header["footstep_side"], dtype=np.int8)
    return data, header["meta"]
