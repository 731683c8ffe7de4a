"""A seeded random sample of error-contract cases across every surface of gaitshift (issue 28).

    PYTHONPATH=src MUJOCO_GL=egl .venv/bin/python benchmarks/contract_sample.py [-n 10000] [--seed 0]
        [--json contract_sample.json] [--timeout 30]

Each case (benchmarks/contract_cases.py, contract_api.py: CLI commands with hostile flags and files,
mutated scenario, robot and campaign YAML, damaged trajectory, joints and campaign files, output names,
Python API calls with random arguments) runs in this process (the CLI through ``gaitshift.cli.main``)
under a per-case timeout, and is classified:

* ``result``: exit 0 or 1 (a result that reports a failure), every file it promised written, whole
  (a trajectory loads under the file contract), no NaN/Infinity in JSON on stdout, no temporary file;
* ``refused``: exit 2 (an API call: a ``GaitshiftError``) with exactly one line
  ``gaitshift: error: <field> = <value> is invalid: allowed ...`` naming a field of that input, and no
  file left behind;
* ``BAD``: anything else: a traceback or another exception, a wrong exit code, a message that is not
  one line or names no field, a file left after a refusal, a partial or empty output, NaN in the
  output, a numpy RuntimeWarning (it would reach stderr), or the timeout.

Writes a JSON summary (counts per surface and class, the seed, the wall time, every BAD case) and
prints the BAD ones. Exit code 1 when any case is BAD.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import random
import shutil
import signal
import sys
import tempfile
import time
import traceback
import warnings
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))
os.environ.setdefault("MUJOCO_GL", "egl")

import gaitshift
from contract_api import api_case
from contract_cases import (
    Base,
    Case,
    export_case,
    joints_case,
    locomotion_case,
    report_case,
    robot_case,
    scenario_case,
    spec_case,
    stiffness_case,
    teleop_case,
    trajectory_case,
)
from contract_flags import flags_case, out_name_case, simulate_case

#: surface -> (case builder, weight in the sample)
SURFACES: dict[str, tuple[Callable[[random.Random, Path, Base], Case], int]] = {
    "stiffness": (stiffness_case, 8),
    "scenario": (scenario_case, 14),
    "locomotion": (locomotion_case, 10),
    "trajectory": (trajectory_case, 14),
    "teleop": (teleop_case, 5),
    "out_names": (out_name_case, 10),
    "simulate": (simulate_case, 8),
    "flags": (flags_case, 8),
    "robot": (robot_case, 5),
    "spec": (spec_case, 8),
    "report": (report_case, 3),
    "joints": (joints_case, 3),
    "export": (export_case, 3),
    "api": (api_case, 14),
}
PREFIX = "gaitshift: error: "


@dataclass
class Outcome:
    """How one case ended: ``kind`` is ``result``, ``refused`` or ``BAD`` (``why`` says what)."""

    kind: str
    why: str = ""
    code: int | None = None
    line: str = ""


class CaseTimeout(Exception):
    """The case ran past its time limit."""


def _alarm(signum: int, frame: Any) -> None:
    raise CaseTimeout


def _listing(folder: Path) -> set[str]:
    return {str(p.relative_to(folder)) for p in folder.rglob("*")}


def run_case(case: Case, folder: Path, timeout: float) -> Outcome:
    """Run ``case`` (its files are in ``folder``) and classify it (module docstring). A timer already
    running (pytest-timeout's) is put back afterwards, less the time spent."""
    before = _listing(folder)
    cwd = os.getcwd()
    os.chdir(folder)  # a default relative output (robot tune's tune-work/) lands where it is seen
    try:
        return _run_here(case, folder, timeout, before)
    finally:
        os.chdir(cwd)


def _run_here(case: Case, folder: Path, timeout: float, before: set[str]) -> Outcome:
    out, err = io.StringIO(), io.StringIO()
    code: int | None = None
    previous = signal.signal(signal.SIGALRM, _alarm)
    left, _ = signal.getitimer(signal.ITIMER_REAL)
    start = time.monotonic()
    with (
        warnings.catch_warnings(record=True) as caught,
        contextlib.redirect_stdout(out),
        contextlib.redirect_stderr(err),
    ):
        warnings.simplefilter("always")
        signal.setitimer(signal.ITIMER_REAL, min(timeout, left) if left else timeout)
        try:
            code = _execute(case, err)
        except CaseTimeout:
            return Outcome("BAD", f"timeout after {timeout:g} s")
        except Exception as exc:  # any other exception is what the sample hunts
            tb = traceback.format_exception(exc)
            return Outcome("BAD", f"{type(exc).__name__}: {str(exc)[:200]} @ {_where(tb)}")
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, previous)
            if left:
                signal.setitimer(signal.ITIMER_REAL, max(left - (time.monotonic() - start), 1e-3))
    noisy = [w for w in caught if issubclass(w.category, RuntimeWarning)]
    if noisy:
        w = noisy[0]
        return Outcome("BAD", f"RuntimeWarning: {w.message} @ {w.filename}:{w.lineno}", code)
    return classify(case, folder, before, code, out.getvalue(), err.getvalue())


def _execute(case: Case, err: io.StringIO) -> int:
    """Exit code of a CLI case; an API call: 0 on a checked result, 2 on a one-line GaitshiftError
    (printed to ``err`` as the CLI would), 3 on a result with NaN."""
    if case.argv is not None:
        from gaitshift.cli import main

        try:
            main(case.argv)
        except SystemExit as exc:
            return int(exc.code or 0) if not isinstance(exc.code, str) else 99
        return 0
    assert case.call is not None
    try:
        value = case.call()
    except gaitshift.GaitshiftError as exc:
        err.write(PREFIX + str(exc) + "\n")
        return 2
    return 3 if value is False else 0


def _where(tb: list[str]) -> str:
    frames = [line.strip().split("\n")[0] for line in tb if line.strip().startswith("File ")]
    own = [f for f in frames if "gaitshift" in f and "benchmarks" not in f] or frames
    return own[-1] if own else "?"


def classify(case: Case, folder: Path, before: set[str], code: int | None, out: str, err: str) -> Outcome:
    """The outcome of a case that ended with exit ``code`` (module docstring)."""
    if code not in case.codes:
        return Outcome("BAD", f"exit {code} (allowed {case.codes}): {(err or out).strip()[-200:]}", code)
    if "Traceback" in out or "Traceback" in err:
        return Outcome("BAD", "traceback in the output", code)
    after = _listing(folder)
    if code == 2:
        return _refusal(case, err, before, after)
    hidden = sorted(p for p in after - before if Path(p).name.startswith("."))
    if hidden:
        return Outcome("BAD", f"temporary file left: {hidden[:3]}", code)
    for path in case.outputs:
        bad = _output_problem(path)
        if bad:
            return Outcome("BAD", f"{path.name[:60]}: {bad}", code)
    if case.extra.get("json"):
        try:
            json.loads(out, parse_constant=_reject)
        except ValueError as exc:
            return Outcome("BAD", f"stdout is not finite JSON: {exc}", code)
    return Outcome("result", code=code)


def _refusal(case: Case, err: str, before: set[str], after: set[str]) -> Outcome:
    left = sorted(after - before)
    if left:
        return Outcome("BAD", f"files left after the refusal: {left[:3]}", 2)
    if not err.endswith("\n") or err.count("\n") != 1 or not err.startswith(PREFIX):
        return Outcome("BAD", f"not one error line: {err[-300:]!r}", 2)
    line = err[len(PREFIX) : -1]
    field = line.split(" = ", 1)[0] if " = " in line else line.split(": ", 1)[0]
    names = case.names | {n.lstrip("-").replace("-", "_") for n in case.names if n.startswith("--")}
    if line.endswith("(unknown key)") or any(n in field for n in names):
        return Outcome("refused", code=2, line=line)
    if not isinstance_input(line):  # an InfeasibleError: one line saying why no solution exists
        return Outcome("refused", code=2, line=line)
    return Outcome("BAD", f"names no field of the input: {line[:200]}", 2, line)


def isinstance_input(line: str) -> bool:
    """The line has the InputError form ``<field> = <value> is invalid: allowed ...``."""
    return " = " in line and " is invalid: allowed " in line


def _reject(name: str) -> Any:
    raise ValueError(f"{name} in JSON")


def _output_problem(path: Path) -> str:
    """What is wrong with an output a success promised ('' when nothing)."""
    if not path.exists():
        return "missing"
    if path.is_dir():
        return "" if any(path.iterdir()) else "empty folder"
    if path.stat().st_size == 0:
        return "empty file"
    if path.suffix.lower() in (".npz", ".csv", ".json") and path.parent.name != "report":
        try:
            gaitshift.Trajectory.load(path)
        except gaitshift.GaitshiftError as exc:
            return f"does not load: {str(exc)[:150]}"
    return ""


def say(text: str) -> None:
    """Print ``text`` at once (the run's progress, also when stdout is a file)."""
    print(text, flush=True)


def sample(n: int, seed: int, timeout: float, work: Path, log: Callable[[str], None] = say) -> dict[str, Any]:
    """Draw and run ``n`` cases with ``seed`` in the folder ``work``; the summary (module docstring)."""
    rng = random.Random(seed)
    base = Base.make(work / "base")
    names = list(SURFACES)
    weights = [SURFACES[s][1] for s in names]
    counts: dict[str, Counter[str]] = {s: Counter() for s in names}
    bad: list[dict[str, Any]] = []
    start = time.perf_counter()
    for i in range(n):
        surface = rng.choices(names, weights)[0]
        folder = Path(tempfile.mkdtemp(dir=work, prefix=f"{i:05d}-"))
        case_seed = rng.getrandbits(32)
        case = SURFACES[surface][0](random.Random(case_seed), folder, base)
        outcome = run_case(case, folder, timeout)
        counts[surface][outcome.kind] += 1
        if outcome.kind == "BAD":
            entry = {"i": i, "surface": surface, "case_seed": case_seed, "why": outcome.why, "note": case.note}
            entry["argv"] = [a[:120] for a in case.argv] if case.argv else None
            bad.append(entry)
            log(f"BAD #{i} {surface} {case.note}: {outcome.why}\n    {' '.join(entry['argv'] or [])[:300]}")
        shutil.rmtree(folder, ignore_errors=True)
        if (i + 1) % 500 == 0:
            log(f"{i + 1} cases, {time.perf_counter() - start:.0f} s, {len(bad)} BAD")
    wall = time.perf_counter() - start
    totals = Counter[str]()
    for c in counts.values():
        totals.update(c)
    return {
        "seed": seed,
        "cases": n,
        "wall_time_s": round(wall, 1),
        "per_case_ms": round(1e3 * wall / max(n, 1), 1),
        "date": time.strftime("%Y-%m-%d"),
        "totals": dict(totals),
        "surfaces": {s: dict(c) for s, c in counts.items()},
        "bad": bad,
    }


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-n", type=int, default=10_000, help="cases (default 10000)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--timeout", type=float, default=30.0, help="per case, s")
    ap.add_argument("--json", type=Path, default=Path("contract_sample.json"), help="summary file")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="contract-") as work:
        summary = sample(args.n, args.seed, args.timeout, Path(work))
    args.json.write_text(json.dumps(summary, indent=1) + "\n")
    print(json.dumps({k: summary[k] for k in ("seed", "cases", "wall_time_s", "totals")}))
    for s, c in summary["surfaces"].items():
        print(f"  {s:12s} {c}")
    return 1 if summary["bad"] else 0


if __name__ == "__main__":
    sys.exit(main())
