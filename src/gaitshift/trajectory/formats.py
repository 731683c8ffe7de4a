"""The three trajectory file formats: ``.npz``, ``.csv`` and ``.json`` (writers and readers).

This module turns a dict of arrays plus the ``meta`` dict into bytes and back; what the arrays must
contain (keys, shapes, dtypes, NaN rules) is :mod:`gaitshift.trajectory.contract`'s business, which
validates whatever :func:`read` returns. The formats:

* ``.npz``: one ``.npy`` member per array (``numpy.savez_compressed``) and ``meta``, a 0-d unicode
  array holding the JSON text of the meta dict.
* ``.json``: one object: ``meta`` (an object) and one nested list per array; NaN is written ``null``.
* ``.csv``: header lines ``# meta: <JSON>``, ``# footsteps: <JSON>``, ``# footstep_side: <JSON>`` and
  ``# shapes: {key: trailing shape}``, then a column line (``t``, ``com_pos[0]``, ...,
  ``foot_pos[1.2]``) and one row per sample; NaN is an empty cell. Only per-sample arrays (length N)
  have columns; other extras are not stored in CSV.

Every reading failure raises :class:`~gaitshift.errors.TrajectoryFileError` naming the file, the part
at fault (``file``, ``meta``, a key, a header line, a row) and what was found there.
"""

from __future__ import annotations

import csv
import io
import json
import math
import re
import tokenize
import zipfile
import zlib
from collections.abc import Callable
from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.common.atomic import atomic_path
from gaitshift.errors import InputError, TrajectoryFileError

SUFFIXES = (".npz", ".csv", ".json")
#: header lines of the CSV format, in the order they are written
CSV_HEADER = ("meta", "footsteps", "footstep_side", "shapes")
#: arrays of the contract stored in the CSV header instead of columns (they are not per sample)
CSV_HEADER_ARRAYS = ("footsteps", "footstep_side")
#: what reading a damaged .npz can raise: zipfile (BadZipFile, truncated members: EOFError, zlib.error;
#: unsupported compression: NotImplementedError; encrypted members: RuntimeError) and numpy's .npy
#: parser (ValueError: bad header, pickled objects, wrong size; OSError: short reads)
NPZ_ERRORS = (
    OSError,
    ValueError,
    EOFError,
    zipfile.BadZipFile,
    zlib.error,
    NotImplementedError,
    RuntimeError,
    SyntaxError,  # a .npy header numpy cannot parse
    tokenize.TokenError,  # a .npy header cut inside a bracket
)
#: numpy dtype kinds that hold numbers: bool, signed and unsigned int, float
NUMERIC_KINDS = "biuf"


def check_suffix(path: str | Path, field: str) -> str:
    """The lower-case suffix of ``path``; raise :class:`InputError` naming ``field`` unless it is one
    of :data:`SUFFIXES`."""
    suffix = Path(path).suffix.lower()
    if suffix not in SUFFIXES:
        raise InputError(field, str(path), "a file ending in " + ", ".join(SUFFIXES))
    return suffix


# ====================================================================== writing
def write(path: str | Path, arrays: dict[str, np.ndarray], meta: dict[str, Any], n: int) -> Path:
    """Write ``arrays`` (N = ``n`` samples) and ``meta`` to ``path`` in the format of its suffix,
    atomically (a temporary file renamed onto ``path``)."""
    path = Path(path)
    encode = WRITERS[check_suffix(path, "out")]
    with atomic_path(path) as tmp:
        encode(tmp, arrays, meta, n)
    return path


def _write_npz(tmp: Path, arrays: dict[str, np.ndarray], meta: dict[str, Any], _n: int) -> None:
    members: dict[str, Any] = {**arrays, "meta": np.array(json.dumps(meta, allow_nan=False))}
    np.savez_compressed(tmp, **members)


def _write_json(tmp: Path, arrays: dict[str, np.ndarray], meta: dict[str, Any], _n: int) -> None:
    out: dict[str, Any] = {k: null_from_nan(np.asarray(v)) for k, v in arrays.items()}
    out["meta"] = meta
    tmp.write_text(json.dumps(out, allow_nan=False))


def _write_csv(tmp: Path, arrays: dict[str, np.ndarray], meta: dict[str, Any], n: int) -> None:
    buf = io.StringIO()
    buf.write("# meta: " + json.dumps(meta, allow_nan=False) + "\n")
    for key in CSV_HEADER_ARRAYS:
        buf.write(f"# {key}: " + json.dumps(np.asarray(arrays[key]).tolist()) + "\n")
    cols: list[str] = []
    blocks, shapes = [], {}
    for key, arr in arrays.items():
        if key in CSV_HEADER_ARRAYS or len(arr) != n:
            continue
        shapes[key] = list(arr.shape[1:])
        cols += csv_columns(key, shapes[key])
        blocks.append(np.asarray(arr, dtype=float).reshape(n, -1))
    buf.write("# shapes: " + json.dumps(shapes) + "\n")
    buf.write(",".join(cols) + "\n")
    body = io.StringIO()
    np.savetxt(body, np.hstack(blocks), fmt="%.17g", delimiter=",")
    buf.write(body.getvalue().replace("nan", ""))  # numeric block only: NaN -> empty cell
    tmp.write_text(buf.getvalue())


def csv_columns(key: str, trailing: list[int]) -> list[str]:
    """Column names of a per-sample array with trailing shape ``trailing``: ``key`` for a 1-D array,
    else ``key[i.j]`` for every index of the trailing shape, C order."""
    if not trailing:
        return [key]
    return [f"{key}[{'.'.join(map(str, idx))}]" for idx in np.ndindex(*trailing)]


def null_from_nan(arr: np.ndarray) -> Any:
    """Nested lists of ``arr`` with every non-finite float replaced by ``None`` (JSON ``null``)."""
    if arr.dtype.kind == "f":
        obj = arr.astype(object)
        obj[~np.isfinite(arr)] = None
        return obj.tolist()
    return arr.tolist()


WRITERS: dict[str, Callable[[Path, dict[str, np.ndarray], dict[str, Any], int], None]] = {
    ".npz": _write_npz,
    ".json": _write_json,
    ".csv": _write_csv,
}


# ====================================================================== reading
def read(path: str | Path) -> tuple[dict[str, np.ndarray], Any]:
    """Arrays and meta of a trajectory file, decoded by the format of its suffix.

    Raises:
        InputError: the suffix is not one of :data:`SUFFIXES` (field ``file``).
        TrajectoryFileError: no such file, a folder, unreadable, or bytes that are not that format.
    """
    if not isinstance(path, str | PathLike) or isinstance(path, bytes):
        raise InputError("file", path, "a path (str or os.PathLike) of a .npz, .csv or .json file")
    path = Path(path)
    decode = READERS[check_suffix(path, "file")]
    src = str(path)
    if not path.exists():
        raise TrajectoryFileError(src, "file", "no such file", "an existing trajectory file")
    if not path.is_file():
        raise TrajectoryFileError(src, "file", "not a regular file (a folder?)", "a trajectory file")
    return decode(path, src)


def _read_npz(path: Path, src: str) -> tuple[dict[str, np.ndarray], Any]:
    allowed = "a .npz archive of .npy arrays (numpy.savez) as written by gaitshift"
    try:
        archive = np.load(path, allow_pickle=False)
    except NPZ_ERRORS as exc:
        raise TrajectoryFileError(src, "file", f"unreadable ({_first_line(exc)})", allowed) from None
    if not isinstance(archive, np.lib.npyio.NpzFile):
        raise TrajectoryFileError(src, "file", "a single .npy array", allowed)
    data: dict[str, np.ndarray] = {}
    with archive:
        for key in archive.files:
            try:
                value = archive[key]
            except NPZ_ERRORS as exc:
                raise TrajectoryFileError(src, key, f"an unreadable member ({_first_line(exc)})", allowed) from None
            if not isinstance(value, np.ndarray):
                raise TrajectoryFileError(src, key, "a member that is not a .npy array", allowed)
            data[key] = value
    if "meta" not in data:
        raise TrajectoryFileError(src, "meta", "missing", "a 0-d string array holding the meta JSON object")
    meta = data.pop("meta")
    if meta.shape != () or meta.dtype.kind != "U":
        raise TrajectoryFileError(
            src, "meta", f"dtype {meta.dtype} shape {meta.shape}", "a 0-d string array holding the meta JSON object"
        )
    return data, _json_value(str(meta), src, "meta")


def _read_json(path: Path, src: str) -> tuple[dict[str, np.ndarray], Any]:
    raw = _json_value(_text(path, src), src, "file")
    if not isinstance(raw, dict):
        raise TrajectoryFileError(src, "file", f"a JSON {type(raw).__name__}", "a JSON object of arrays and meta")
    if "meta" not in raw:
        raise TrajectoryFileError(src, "meta", "missing", "a JSON object under the key meta")
    meta = raw.pop("meta")
    return {k: array_from_json(v, src, k) for k, v in raw.items()}, meta


def _read_csv(path: Path, src: str) -> tuple[dict[str, np.ndarray], Any]:
    lines = _text(path, src).splitlines()
    header: dict[str, Any] = {}
    body = 0
    while body < len(lines) and lines[body].startswith("#"):
        key, sep, value = lines[body][1:].strip().partition(":")
        where = f"header line {body + 1}"
        if not sep or key not in CSV_HEADER:
            raise TrajectoryFileError(src, where, repr(_clip(lines[body])), _header_allowed())
        header[key] = _json_value(value, src, f"header {key}")
        body += 1
    for key in CSV_HEADER:
        if key not in header:
            raise TrajectoryFileError(src, f"header {key}", "missing", _header_allowed())
    data = {k: array_from_json(header[k], src, k) for k in CSV_HEADER_ARRAYS}
    data.update(_csv_columns(lines[body:], header["shapes"], src, body))
    return data, header["meta"]


def _csv_columns(lines: list[str], shapes: Any, src: str, offset: int) -> dict[str, np.ndarray]:
    """The per-sample arrays of a CSV body (column line + rows), laid out by the ``shapes`` header."""
    names, widths = _csv_layout(shapes, src)
    try:
        rows = list(csv.reader(lines))
    except csv.Error as exc:
        raise TrajectoryFileError(src, "file", f"not CSV ({_first_line(exc)})", "comma-separated numbers") from None
    if not rows or rows[0] != names:
        found = repr(_clip(",".join(rows[0]))) if rows else "missing"
        raise TrajectoryFileError(src, f"column line {offset + 1}", found, "the columns " + _clip(",".join(names)))
    for i, row in enumerate(rows[1:]):
        if len(row) != len(names):
            where = f"row {offset + i + 2}"
            raise TrajectoryFileError(src, where, f"{len(row)} cells", f"{len(names)} cells, one per column")
    cells = [c if c.strip() else "nan" for row in rows[1:] for c in row]
    try:
        values = np.fromiter(map(float, cells), float, len(cells)).reshape(len(rows) - 1, len(names))
    except ValueError:
        k = next(k for k, c in enumerate(cells) if not _is_float(c))
        where = f"row {offset + 2 + k // len(names)} column {names[k % len(names)]}"
        raise TrajectoryFileError(src, where, repr(_clip(cells[k])), "a number or an empty cell (NaN)") from None
    data, pos = {}, 0
    for (key, trailing), width in zip(shapes.items(), widths, strict=True):
        data[key] = values[:, pos : pos + width].reshape(len(values), *trailing)
        pos += width
    return data


def _csv_layout(shapes: Any, src: str) -> tuple[list[str], list[int]]:
    """Column names and widths from the ``shapes`` header, checked before anything is allocated."""
    allowed = 'an object {key: trailing shape as a list of positive integers}, e.g. {"com_pos": [3]}'
    if not isinstance(shapes, dict):
        raise TrajectoryFileError(src, "header shapes", _clip(json.dumps(shapes)), allowed)
    widths = []
    for key, trailing in shapes.items():
        ok = isinstance(trailing, list) and all(type(d) is int and 1 <= d <= 1000 for d in trailing)
        if not ok or len(trailing) > 4 or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", key):
            raise TrajectoryFileError(src, f"header shapes.{_clip(key)}", _clip(json.dumps(trailing)), allowed)
        widths.append(math.prod(trailing))
    if sum(widths) > 100_000:
        raise TrajectoryFileError(src, "header shapes", f"{sum(widths)} columns", "at most 100000 columns")
    return [name for key, trailing in shapes.items() for name in csv_columns(key, trailing)], widths


def array_from_json(value: Any, src: str, key: str) -> np.ndarray:
    """A float array from nested JSON lists of numbers, ``null`` (NaN) and booleans (0/1).

    Raises:
        TrajectoryFileError: ragged lists, strings, objects, or integers beyond float range.
    """
    allowed = "nested lists of numbers (null for NaN) with a rectangular shape"
    try:
        arr = np.asarray(value)
    except (ValueError, TypeError, RecursionError) as exc:  # ragged or too deeply nested lists
        raise TrajectoryFileError(src, key, _first_line(exc), allowed) from None
    if arr.dtype.kind == "O":  # null, or integers beyond int64, among the numbers
        kinds = {type(x) for x in arr.flat} - {type(None), bool, int, float}
        if kinds:
            found = "entries of type " + ", ".join(sorted(k.__name__ for k in kinds))
            raise TrajectoryFileError(src, key, found, allowed)
        try:
            arr = np.where(arr == None, math.nan, arr).astype(float)  # noqa: E711 (element-wise)
        except OverflowError:
            raise TrajectoryFileError(src, key, "an integer beyond the float range", allowed) from None
    if arr.dtype.kind not in NUMERIC_KINDS:
        raise TrajectoryFileError(src, key, f"entries of dtype {arr.dtype}", allowed)
    return arr.astype(float)


def _json_value(text: str, src: str, key: str) -> Any:
    """``json.loads`` with every failure (syntax, nesting depth, huge integers) as a file error."""
    try:
        return json.loads(text)
    except (ValueError, RecursionError) as exc:  # JSONDecodeError is a ValueError
        raise TrajectoryFileError(src, key, f"text that is not JSON ({_first_line(exc)})", "valid JSON") from None


def _text(path: Path, src: str) -> str:
    try:
        return path.read_bytes().decode("utf-8")
    except UnicodeDecodeError as exc:
        raise TrajectoryFileError(
            src, "file", f"bytes that are not UTF-8 ({exc.reason} at byte {exc.start})", "UTF-8 text"
        ) from None
    except OSError as exc:
        raise TrajectoryFileError(src, "file", f"unreadable ({exc.strerror})", "a readable file") from None


def _header_allowed() -> str:
    return "header lines '# <key>: <JSON>' for " + ", ".join(CSV_HEADER)


def _is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    return _clip(text[0]) if text else type(exc).__name__


def _clip(text: str, limit: int = 80) -> str:
    """``text`` shortened to ``limit`` characters on one line (for messages)."""
    text = text.replace("\n", " ").replace("\r", " ")
    return text if len(text) <= limit else text[: limit - 3] + "..."


READERS: dict[str, Callable[[Path, str], tuple[dict[str, np.ndarray], Any]]] = {
    ".npz": _read_npz,
    ".json": _read_json,
    ".csv": _read_csv,
}
