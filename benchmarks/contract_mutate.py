"""Hostile edits for the contract sample (benchmarks/contract_sample.py): garbage values, edits of a
nested YAML/JSON document, damaged text and bytes, hostile flag text and output names.

Every function draws from a ``random.Random``, so the same code serves the seeded sample and the
hypothesis tests (``st.randoms(use_true_random=False)`` hands them a shrinkable ``Random``).
"""

from __future__ import annotations

import json
import math
import random
from pathlib import Path
from typing import Any

from pydantic import BaseModel

#: numbers a field must survive
NUMBERS = [0, -1, 1, 2, 0.5, -0.0, 1e-300, 1e300, -1e300, 1e9, 2**63, 10**30, math.nan, math.inf, -math.inf]
#: text a field must survive
TEXTS = ["", "abc", "nan", "inf", "1e999", "-", "é", "x" * 300, "0x10", "[1, 2]", "{a: 1}", "null", "\t"]
#: flag text a numeric flag must survive (valid-looking values weigh more)
FLAG_TEXT = ["nan", "inf", "-inf", "1e308", "1e999", "-1", "0", "1e-300", "abc", "", "0x10", "1_0", "2", "0.5"]


def garbage(rng: random.Random, depth: int = 0) -> Any:
    """A hostile value: None, a boolean, a number of :data:`NUMBERS`, a small float, a text, or (at most
    two levels deep) a list or a mapping of such values."""
    kind = rng.randrange(7 if depth < 2 else 5)
    if kind == 0:
        return rng.choice([None, True, False])
    if kind == 1:
        return rng.choice(NUMBERS)
    if kind == 2:
        return round(rng.uniform(-10, 10), rng.randrange(4))
    if kind == 3:
        return rng.choice(TEXTS)
    if kind == 4:
        return rng.randrange(-3, 100)
    if kind == 5:
        return [garbage(rng, depth + 1) for _ in range(rng.randrange(4))]
    return {rng.choice(["a", "t", "x", "left", "vx", "gait"]): garbage(rng, depth + 1) for _ in range(rng.randrange(3))}


def paths(node: Any, prefix: tuple = ()) -> list[tuple]:
    """Every path into a nested dict/list (the root is ``()``)."""
    out = [prefix]
    items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else []
    for k, v in items:
        out += paths(v, (*prefix, k))
    return out


def _get(node: Any, path: tuple) -> Any:
    for k in path:
        node = node[k]
    return node


def mutate(data: Any, rng: random.Random, edits: int) -> tuple[Any, set[str]]:
    """A deep copy of the JSON-like ``data`` after ``edits`` hostile edits (delete, add a key, replace
    by garbage, scale a number); returns it and the keys added (a message may name them)."""
    data = json.loads(json.dumps(data))
    added: set[str] = set()
    for _ in range(edits):
        path = rng.choice(paths(data))
        node = _get(data, path) if path else data
        op = rng.choice(["delete", "add", "replace", "replace", "scale", "scale"])
        if op == "scale" and path and isinstance(node, int | float) and not isinstance(node, bool):
            factor = rng.choice([0, -1, 1e-3, 0.1, 0.5, 2, 10, 1e3, 1e6, 1e300])
            value = node * factor
            _get(data, path[:-1])[path[-1]] = int(value) if isinstance(node, int) and abs(value) < 1e18 else value
        elif op == "add" and isinstance(node, dict):
            key = rng.choice(["extra", "Height", "t", "zz", "é", "1"])
            node[key] = garbage(rng)
            added.add(key)
        elif op == "delete" and path:
            del _get(data, path[:-1])[path[-1]]
        elif path:
            _get(data, path[:-1])[path[-1]] = garbage(rng)
    return data, added


def damage_text(text: str, rng: random.Random) -> bytes:
    """``text`` as UTF-8 bytes, mostly whole (3 in 5), else truncated, with junk inserted, or as bytes
    that are not UTF-8."""
    raw = text.encode()
    how = rng.choice(["none", "none", "none", "truncate", "insert", "bytes"])
    if how == "truncate":
        return raw[: rng.randrange(len(raw) + 1)]
    at = rng.randrange(len(raw) + 1)
    if how == "insert":
        return (
            raw[:at]
            + rng.choice([b":", b"- ", b"{", b"]", b"\n  x: [", b"\t", b"&a *a", b"!!python/object:os"])
            + raw[at:]
        )
    if how == "bytes":
        return raw[:at] + bytes(rng.randrange(256) for _ in range(rng.randrange(1, 6))) + b"\xff" + raw[at:]
    return raw


def damage_bytes(raw: bytes, rng: random.Random) -> bytes:
    """``raw`` truncated, overwritten in part, emptied, prefixed or appended to."""
    how = rng.choice(["truncate", "truncate", "overwrite", "empty", "prefix", "append"])
    junk = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 17)))
    if how == "truncate":
        return raw[: rng.randrange(max(len(raw), 1))]
    if how == "overwrite":
        at = rng.randrange(max(len(raw), 1))
        return raw[:at] + junk + raw[at + len(junk) :]
    if how == "empty":
        return b""
    return junk + raw if how == "prefix" else raw + junk


def schema_names(model: type[BaseModel], out: set[str] | None = None) -> set[str]:
    """Every field name of a pydantic model and of the models inside it (a message names one)."""
    out = set() if out is None else out
    for name, info in model.model_fields.items():
        out.add(name)
        for sub in _models_in(info.annotation):
            if sub.__name__ not in out:
                out.add(sub.__name__)
                schema_names(sub, out)
    return out


def _models_in(annotation: Any) -> list[type[BaseModel]]:
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return [annotation]
    return [m for arg in getattr(annotation, "__args__", ()) for m in _models_in(arg)]


def hostile_name(rng: random.Random, folder: Path, suffix: str, kind: str | None = None) -> tuple[Path, str]:
    """An output path in ``folder`` (which holds ``file.npz``, a file, and ``dir.npz``, a folder): valid
    (``ok``, ``upper``: the suffix in upper case, ``nested``: in a new sub-folder) or hostile; returns
    (path, kind)."""
    kind = kind or rng.choice(list(NAME_KINDS))
    return NAME_KINDS[kind](folder, suffix), kind


NAME_KINDS = {
    "ok": lambda f, s: f / f"out{s}",
    "upper": lambda f, s: f / f"out{s.upper()}",
    "nested": lambda f, s: f / "new" / f"out{s}",
    "long_name": lambda f, s: f / ("a" * 300 + s),
    "long_245": lambda f, s: f / ("b" * 245 + s),
    "long_folder": lambda f, s: f / ("c" * 300) / f"out{s}",
    "long_path": lambda f, s: f.joinpath(*["d" * 200] * 21, f"out{s}"),
    "under_file": lambda f, s: f / "file.npz" / f"out{s}",
    "folder": lambda f, s: f / "dir.npz",
    "no_suffix": lambda f, s: f / "out",
    "bad_suffix": lambda f, s: f / "out.txt",
    "dot": lambda f, s: f / s,
    "proc": lambda f, s: Path(f"/proc/gaitshift/out{s}"),
}
#: kinds that are valid output names (the command may succeed)
VALID_NAMES = ("ok", "upper", "nested")
