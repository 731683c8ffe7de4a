"""Fuzzing the CLI's error contract with hypothesis: every hostile input ends in a result or one line.

Mutated scenario YAML files (``plan``), mutated trajectory files in the three formats (``check``),
random teleop key scripts (``teleop --script``) and hostile flag values (``stiffness``, ``--out``,
``--max-time``) are run through the real CLI in-process. Each run must end with exit code 0 (a
result), 1 (``check`` found a physics violation, and said so in its report) or 2 (one line on stderr,
``gaitshift: error: <field> = <value> is invalid: allowed ...``, naming a field of that input); never
a traceback, never an output file or a temporary file after a failure, and never NaN or Infinity in
``--json`` output. The examples are derandomized (same inputs every run) and nothing is written to a
hypothesis database.
"""

from __future__ import annotations

import json
import math
import os
import re
import sys
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st
from hypothesis.control import currently_in_test_context
from pydantic import BaseModel

import gaitshift
from gaitshift.scenario.commands import ACTIONS
from gaitshift.scenario.fields import model_at
from gaitshift.scenario.loader import SCHEMAS
from gaitshift.trajectory import formats
from gaitshift.trajectory.contract import CONTRACT_KEYS

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
from contract_cases import TVLIP, VHIP  # the contract sample's base inputs: one copy

FUZZ = settings(
    derandomize=True,
    deadline=None,
    database=None,
    print_blob=False,
    suppress_health_check=[
        HealthCheck.function_scoped_fixture,
        HealthCheck.too_slow,
        HealthCheck.data_too_large,
        HealthCheck.large_base_example,
    ],
)
#: examples per property (sum >= 500; the 18 out-path cases are all there are), derandomized: the same every
#: run; the contract's wider sample, 10 000 cases, is benchmarks/contract_sample.py's (README)
EXAMPLES = {"scenario": 250, "trajectory": 300, "script": 120, "stiffness": 120, "out": 18}

BASES = {"tvlip": TVLIP, "vhip": VHIP}

NUMBERS = [0, -1, 1, 2, 0.5, -0.0, 1e-300, 1e300, -1e300, 1e9, 2**63, 10**30, math.nan, math.inf, -math.inf]
SCALARS = st.one_of(
    st.none(),
    st.booleans(),
    st.sampled_from(NUMBERS),
    st.floats(-10, 10, allow_nan=False),
    st.text(max_size=8),
)
GARBAGE = st.recursive(
    SCALARS,
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=5), inner, max_size=3),
    max_leaves=5,
)


# ====================================================================== running the CLI


def _reject_constant(name: str) -> Any:
    raise AssertionError(f"{name} in JSON output")


def assert_contract(
    result: tuple[int, str, str],
    folder: Path,
    before: set[str],
    outputs: tuple[Path, ...],
    names: set[str],
    codes: tuple[int, ...] = (0, 2),
    as_json: bool = False,
) -> str:
    """The error contract for one run; returns the error line ('' on success)."""
    code, out, err = result
    _event(f"exit {code}")
    assert code in codes, (code, out[-500:], err[-500:])
    assert "Traceback" not in out and "Traceback" not in err
    after = set(os.listdir(folder))
    if code == 0:
        assert after == before | {p.name for p in outputs}, sorted(after ^ before)
    else:
        assert after == before, f"files left after a failure: {sorted(after - before)}"
    if as_json and code in (0, 1):
        report = json.loads(out, parse_constant=_reject_constant)
        assert (code == 1) == (not all(report["pass"].values()))
    if code != 2:
        return ""
    assert err.endswith("\n") and err.count("\n") == 1, err
    assert err.startswith("gaitshift: error: "), err
    line = err[len("gaitshift: error: ") : -1]
    field = line.split(" = ", 1)[0] if " = " in line else line.split(": ", 1)[0]
    _event("field " + re.sub(r"[0-9]+", "#", field.rsplit("/", 1)[-1])[:40])
    unknown_key = line.endswith("(unknown key)")  # the field is the unknown key itself
    assert unknown_key or any(n in field for n in names), f"no field of {sorted(names)[:12]}... named in: {line}"
    return line


def _event(text: str) -> None:
    """Count ``text`` in hypothesis' statistics (``--hypothesis-show-statistics``) inside a property."""
    if currently_in_test_context():
        event(text)


def case_folder(tmp_path: Path) -> Path:
    return Path(tempfile.mkdtemp(dir=tmp_path))


# ====================================================================== (a) scenario YAML
def _schema_names(model: type[BaseModel], out: set[str]) -> set[str]:
    for name in model.model_fields:
        out.add(name)
        sub = model_at(model, [name])
        if sub is not None:
            _schema_names(sub, out)
    return out


SCENARIO_NAMES = set().union(*(_schema_names(m, set()) for m in SCHEMAS.values())) | {"scenario", "planner"}


def _paths(node: Any, prefix: tuple = ()) -> list[tuple]:
    """Every path into a nested dict/list (the root is ``()``)."""
    out = [prefix]
    items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else []
    for k, v in items:
        out += _paths(v, (*prefix, k))
    return out


def _get(node: Any, path: tuple) -> Any:
    for k in path:
        node = node[k]
    return node


@st.composite
def mutated_scenarios(draw) -> tuple[str, set[str]]:
    """(YAML text, names a message may use) of a valid short scenario after 1-3 hostile edits."""
    planner = draw(st.sampled_from(sorted(BASES)))
    data = json.loads(json.dumps(BASES[planner]))
    added: set[str] = set()
    for _ in range(draw(st.integers(1, 3))):
        path = draw(st.sampled_from(_paths(data)))
        node = _get(data, path)
        op = draw(st.sampled_from(["delete", "add", "replace", "replace", "scale", "scale"]))
        if op == "scale" and path and isinstance(node, int | float) and not isinstance(node, bool):
            factor = draw(st.sampled_from([0, -1, 1e-3, 0.1, 0.5, 2, 10, 1e3, 1e6]))
            _get(data, path[:-1])[path[-1]] = type(node)(node * factor)
        elif op == "add" and isinstance(node, dict):
            key = draw(st.text(min_size=1, max_size=6))
            node[key] = draw(GARBAGE)
            added.add(key)
        elif op == "delete" and path:
            parent = _get(data, path[:-1])
            del parent[path[-1]]
        elif path:
            _get(data, path[:-1])[path[-1]] = draw(GARBAGE)
    text = yaml.safe_dump(data, allow_unicode=True)
    damage = draw(st.sampled_from(["none", "none", "none", "truncate", "bytes"]))
    if damage == "truncate":
        text = text[: draw(st.integers(0, len(text)))]
    elif damage == "bytes":
        at = draw(st.integers(0, len(text)))
        text = text[:at] + draw(st.text(max_size=6)) + text[at:]
    return text, SCENARIO_NAMES | added


@settings(FUZZ, max_examples=EXAMPLES["scenario"])
@given(case=mutated_scenarios(), suffix=st.sampled_from(formats.SUFFIXES))
def test_mutated_scenarios_plan_or_fail_in_one_line_without_output(case, suffix, tmp_path, cli):
    text, names = case
    folder = case_folder(tmp_path)
    yml = folder / "scenario.yaml"
    yml.write_bytes(text.encode("utf-8", errors="surrogatepass"))
    out = folder / f"plan{suffix}"
    before = set(os.listdir(folder))
    result = cli(["plan", str(yml), "--out", str(out)])
    assert_contract(result, folder, before, (out,), names)


def test_scenario_bytes_that_are_not_utf8_name_the_file(tmp_path, cli):
    yml = tmp_path / "s.yaml"
    yml.write_bytes(b"height: \xff\xfe\n")
    result = cli(["plan", str(yml), "--out", str(tmp_path / "p.npz")])
    line = assert_contract(result, tmp_path, {"s.yaml"}, (), {"scenario"}, codes=(2,))
    assert "UTF-8" in line


# ====================================================================== (b) trajectory files
class Bases(dict):
    """{file name: (file bytes, arrays, meta)}; its repr stays short in hypothesis reports."""

    def __repr__(self) -> str:
        return f"Bases({sorted(self)})"


@pytest.fixture(scope="module")
def base_trajectories(tmp_path_factory) -> Bases:
    """(file bytes, arrays, meta) of a short TV-LIPM and a short VHIP plan in every format."""
    folder = tmp_path_factory.mktemp("base")
    out = Bases()
    for planner, data in BASES.items():
        traj = gaitshift.plan(gaitshift.load_scenario(data))
        for suffix in formats.SUFFIXES:
            path = traj.save(folder / f"{planner}{suffix}")
            out[f"{planner}{suffix}"] = (path.read_bytes(), traj.arrays(), dict(traj.meta))
    return out


def _encode_npz(path: Path, arrays: dict[str, Any], meta: Any) -> None:
    members = dict(arrays)  # an extra array named "meta" stands in for the meta member
    if meta is not _DROP and "meta" not in members:
        members["meta"] = np.array(json.dumps(meta, default=str))
    with open(path, "wb") as f:
        np.savez(f, **members)


def _encode_json(path: Path, arrays: dict[str, Any], meta: Any) -> None:
    obj: dict[str, Any] = {k: np.asarray(v).tolist() for k, v in arrays.items()}
    if meta is not _DROP and "meta" not in obj:
        obj["meta"] = meta
    path.write_text(json.dumps(obj, default=str))


def _encode_csv(path: Path, arrays: dict[str, Any], meta: Any) -> None:
    n = len(np.atleast_1d(arrays.get("t", np.zeros(2))))
    lines = [] if meta is _DROP else ["# meta: " + json.dumps(meta, default=str)]
    for key in formats.CSV_HEADER_ARRAYS:
        if key in arrays:
            lines.append(f"# {key}: " + json.dumps(np.asarray(arrays[key]).tolist(), default=str))
    cols = {k: np.asarray(v) for k, v in arrays.items() if k not in formats.CSV_HEADER_ARRAYS}
    cols = {k: v for k, v in cols.items() if v.ndim >= 1 and len(v) == n}
    lines.append("# shapes: " + json.dumps({k: list(v.shape[1:]) for k, v in cols.items()}))
    lines.append(",".join(c for k, v in cols.items() for c in formats.csv_columns(k, list(v.shape[1:]))))
    flat = [(v.astype(int) if v.dtype == bool else v).reshape(n, math.prod(v.shape[1:])) for v in cols.values()]
    lines += [",".join("" if str(x) == "nan" else str(x) for b in flat for x in b[i]) for i in range(n)]
    path.write_text("\n".join(lines) + "\n")


ENCODERS = {".npz": _encode_npz, ".json": _encode_json, ".csv": _encode_csv}
_DROP = object()


@st.composite
def mutated_arrays(draw, arrays: dict[str, np.ndarray], meta: dict) -> tuple[dict[str, Any], Any]:
    """The arrays and meta of a valid plan after one hostile structural edit."""
    arrays = {k: np.array(v) for k, v in arrays.items()}
    meta = json.loads(json.dumps(meta))
    key = draw(st.sampled_from(sorted(arrays)))
    arr = arrays[key]
    ops = ["drop", "extra", "reshape", "dtype", "inject", "inject", "meta", "meta_drop", "scale", "phase"]
    op = draw(st.sampled_from(ops))
    if op == "scale" and arr.dtype.kind == "f":  # a valid file with wrong physics: check must say so
        arrays[key] = arr * draw(st.sampled_from([0.0, -1.0, 1.001, 10.0, 1e3, 1e5]))
    elif op == "phase":  # phases and contacts changed consistently over a stretch of samples
        n = len(arrays["t"])
        a, b = sorted(draw(st.lists(st.integers(0, n), min_size=2, max_size=2)))
        phase = draw(st.sampled_from([0, 1, 2]))
        arrays["phase"][a:b] = phase
        arrays["contact"][a:b] = {0: [True, True], 1: [draw(st.booleans())] * 2, 2: [False, False]}[phase]
        if phase == 1:
            arrays["contact"][a:b, 1] = ~arrays["contact"][a:b, 0]
    elif op == "drop":
        del arrays[key]
    elif op == "extra":
        name = draw(st.sampled_from(["extra", "t", "meta", "a b", "boundary_t", "x" * 3]))
        arrays[name] = np.array(draw(GARBAGE), dtype=object) if draw(st.booleans()) else np.full(3, np.inf)
    elif op == "reshape":
        how = draw(st.sampled_from(["flat", "T", "head", "axis", "empty"]))
        arrays[key] = {
            "flat": lambda a: a.reshape(-1),
            "T": lambda a: a.T,
            "head": lambda a: a[: draw(st.integers(0, 3))],
            "axis": lambda a: a[..., None],
            "empty": lambda a: a[:0],
        }[how](arr)
    elif op == "dtype":
        dtype = draw(st.sampled_from([str, complex, np.int64, np.float32, bool, object]))
        with np.errstate(invalid="ignore"):  # NaN -> int is part of the damage
            arrays[key] = arr.astype(dtype)
    elif op == "inject" and arr.size:
        flat = arr.astype(float).reshape(-1)
        flat[draw(st.integers(0, flat.size - 1))] = draw(
            st.sampled_from([math.nan, math.inf, -math.inf, 1e300, -1e7, 7])
        )
        arrays[key] = flat.reshape(arr.shape)
    elif op == "meta":
        field = draw(st.sampled_from(["planner", "gravity", "foot_size", "scenario", None]))
        if field is None:
            meta = draw(GARBAGE)
        else:
            meta[field] = draw(GARBAGE)
    elif op == "meta_drop":
        meta = (
            _DROP
            if draw(st.booleans())
            else {k: v for k, v in meta.items() if k != draw(st.sampled_from(sorted(meta)))}
        )
    return arrays, meta


@st.composite
def damaged_files(draw, base: dict) -> tuple[str, bytes | None, tuple | None]:
    """(base name, damaged bytes or None, mutated arrays/meta or None)."""
    name = draw(st.sampled_from(sorted(base)))
    raw, arrays, meta = base[name]
    kind = draw(st.sampled_from(["bytes", "structure", "structure"]))
    if kind == "structure":
        return name, None, draw(mutated_arrays(arrays, meta))
    op = draw(st.sampled_from(["truncate", "overwrite", "empty", "prefix", "append"]))
    if op == "truncate":
        raw = raw[: draw(st.integers(0, len(raw) - 1))]
    elif op == "overwrite":
        at = draw(st.integers(0, len(raw) - 1))
        junk = draw(st.binary(min_size=1, max_size=16))
        raw = raw[:at] + junk + raw[at + len(junk) :]
    elif op == "empty":
        raw = b""
    elif op == "prefix":
        raw = draw(st.binary(min_size=1, max_size=8)) + raw
    else:
        raw = raw + draw(st.binary(min_size=1, max_size=8))
    return name, raw, None


TRAJECTORY_NAMES = set(CONTRACT_KEYS) | {"file", "meta", "header", "row", "column", "extra", "boundary_t", "a b"}


@settings(FUZZ, max_examples=EXAMPLES["trajectory"])
@given(data=st.data())
def test_damaged_trajectory_files_check_or_fail_in_one_line(base_trajectories, data, tmp_path, cli):
    name, raw, mutated = data.draw(damaged_files(base_trajectories))
    folder = case_folder(tmp_path)
    path = folder / f"traj{Path(name).suffix}"
    if raw is not None:
        path.write_bytes(raw)
    else:
        arrays, meta = mutated
        ENCODERS[path.suffix](path, arrays, meta)
    before = set(os.listdir(folder))
    result = cli(["check", str(path), "--json"])
    line = assert_contract(result, folder, before, (), TRAJECTORY_NAMES, codes=(0, 1, 2), as_json=True)
    assert not line or line.startswith(f"{path}: ")


def test_a_folder_or_a_missing_file_is_named_as_such(tmp_path, cli):
    (tmp_path / "d.npz").mkdir()
    line = assert_contract(cli(["check", str(tmp_path / "d.npz")]), tmp_path, {"d.npz"}, (), {"file"}, (2,))
    assert "folder" in line
    line = assert_contract(cli(["check", str(tmp_path / "x.csv")]), tmp_path, {"d.npz"}, (), {"file"}, (2,))
    assert "no such file" in line


# ====================================================================== (c) command scripts
TOKENS = st.one_of(
    st.sampled_from([*ACTIONS, "wait=0.3", "wait=1"]),  # valid tokens weigh twice
    st.sampled_from(
        [*ACTIONS, "UP", "Stop", "wait=0.2", "wait:0.5", "wait=1e9", "wait=-1", "wait=nan", "wait=", "wait"]
    ),
    st.floats(allow_nan=True, allow_infinity=True).map(lambda x: f"wait={x!r}"),
    st.text(min_size=1, max_size=6),
)


@pytest.fixture(scope="module")
def vhip_yaml(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("vhip") / "short.yaml"
    path.write_text(yaml.safe_dump(VHIP))
    return path


@settings(FUZZ, max_examples=EXAMPLES["script"])
@given(
    tokens=st.lists(TOKENS, max_size=6),
    sep=st.sampled_from([" ", ",", ";", "\n", " , "]),
    max_time=st.sampled_from(["1.5"] * 6 + ["nan", "-1", "0", "inf", "1e9", "abc"]),
    suffix=st.sampled_from([*formats.SUFFIXES] * 3 + [".txt", ""]),
)
def test_random_key_scripts_run_or_fail_in_one_line(vhip_yaml, tokens, sep, max_time, suffix, tmp_path, cli):
    folder = case_folder(tmp_path)
    out = folder / f"teleop{suffix}"
    argv = ["teleop", str(vhip_yaml), "--script", sep.join(tokens), "--max-time", max_time, "--out", str(out)]
    result = cli(argv)
    line = assert_contract(result, folder, set(), (out,), {"--script", "--max-time", "--out"})
    if result[0] == 0:
        assert gaitshift.Trajectory.load(out).meta["planner"] == "vhip"
    else:
        assert line


# ====================================================================== (d) flags
FLOAT_TEXT = st.one_of(
    st.sampled_from(["nan", "inf", "-inf", "1e308", "1e999", "-1", "0", "1e-300", "abc", "", "0x10", "1_0"]),
    st.floats(min_value=-1e3, max_value=1e3).map(repr),
    st.floats(min_value=0.01, max_value=2.0).map(repr),
    st.floats(min_value=0.01, max_value=2.0).map(repr),
)
STIFFNESS_FLAGS = ("--height", "--single-support", "--double-support", "--flight", "--gravity")


@settings(FUZZ, max_examples=EXAMPLES["stiffness"])
@given(values=st.lists(FLOAT_TEXT, min_size=5, max_size=5), keep=st.lists(st.booleans(), min_size=5, max_size=5))
def test_stiffness_flags_give_finite_json_or_one_line(values, keep, tmp_path, cli):
    argv = ["stiffness", "--json"]
    for flag, value, k in zip(STIFFNESS_FLAGS, values, keep, strict=True):
        if k or flag != "--gravity":
            argv += [flag, value]
    names = {f.lstrip("-").replace("-", "_") for f in STIFFNESS_FLAGS} | set(STIFFNESS_FLAGS)
    result = cli(argv)
    assert_contract(result, tmp_path, set(os.listdir(tmp_path)), (), names)
    if result[0] == 0:
        assert all(math.isfinite(v) for v in json.loads(result[1], parse_constant=_reject_constant).values())


@pytest.fixture(scope="module")
def tvlip_yaml(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("tvlip") / "short.yaml"
    path.write_text(yaml.safe_dump(TVLIP))
    return path


OUT_KINDS = ["folder", "under_file", "no_suffix", "bad_suffix", "fifo", "proc", "dot", "nested_new", "ok"]


@settings(FUZZ, max_examples=EXAMPLES["out"])
@given(kind=st.sampled_from(OUT_KINDS), command=st.sampled_from(["plan", "plot"]))
def test_hostile_out_paths_fail_before_any_work(tvlip_yaml, kind, command, tmp_path, cli):
    folder = case_folder(tmp_path)
    (folder / "file.npz").write_bytes(b"x")
    os.mkfifo(folder / "fifo.npz")
    (folder / "dir.npz").mkdir()
    out = {
        "folder": folder / "dir.npz",
        "under_file": folder / "file.npz" / "x.npz",
        "no_suffix": folder / "plan",
        "bad_suffix": folder / "plan.txt",
        "fifo": folder / "fifo.npz",
        "proc": Path("/proc/gaitshift/plan.npz"),
        "dot": folder / ".npz",
        "nested_new": folder / "new" / "plan.npz",
        "ok": folder / "plan.json",
    }[kind]
    before = set(os.listdir(folder))
    if command == "plan":
        result = cli(["plan", str(tvlip_yaml), "--out", str(out)])
        outputs = (out,) if out.parent == folder else (out.parent,)
        assert_contract(result, folder, before, outputs, {"--out"})
        assert (result[0] == 0) == (kind in ("ok", "nested_new"))
    elif kind in ("under_file", "fifo", "proc", "bad_suffix"):  # plot: a folder; only the failures (no plotting)
        src = folder / "file.npz"
        result = cli(["plot", str(src), "--out", str(out if kind != "bad_suffix" else src)])
        assert_contract(result, folder, before, (), {"--out"}, codes=(2,))
