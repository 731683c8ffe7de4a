"""The benchmark suite behind ``gaitshift bench``.

Each topic module ``gaitshift.bench.<topic>`` registers functions with :func:`benchmark`. A benchmark
function takes ``quick: bool`` and returns a list of :class:`Result`. Times come from
``time.perf_counter`` over many repetitions after a warm-up; we report the median and the 99th
percentile, and the ratio to a baseline measured in the same run. ``quick`` only checks that every
benchmark runs (few repetitions); it never judges speed.
"""

from __future__ import annotations

import importlib
import json
import os
import platform
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

#: Topic modules, in table order.
TOPICS = ("tvlip", "vhip", "locomotion", "robot", "sim", "estimation", "perception", "slip")


@dataclass(frozen=True)
class Result:
    """One row of the benchmark table. Times in seconds."""

    operation: str
    size: str
    median_s: float
    p99_s: float
    repeats: int
    baseline: str | None = None
    baseline_median_s: float | None = None
    paper: str | None = None
    note: str = ""
    baseline_p99_s: float | None = None

    @property
    def ratio(self) -> float | None:
        """Baseline median over our median (how many times faster we are)."""
        if self.baseline_median_s is None or self.median_s <= 0:
            return None
        return self.baseline_median_s / self.median_s

    def as_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["ratio"] = self.ratio
        return d


_REGISTRY: list[tuple[str, Callable[[bool], list[Result]]]] = []


def benchmark(name: str) -> Callable[[Callable[[bool], list[Result]]], Callable[[bool], list[Result]]]:
    """Register ``fn(quick) -> list[Result]`` under ``name``."""

    def deco(fn: Callable[[bool], list[Result]]) -> Callable[[bool], list[Result]]:
        _REGISTRY.append((name, fn))
        return fn

    return deco


def measure(fn: Callable[[], Any], repeats: int, warmup: int = 3) -> np.ndarray:
    """Wall-clock times of ``repeats`` calls of ``fn`` after ``warmup`` calls, in seconds."""
    for _ in range(warmup):
        fn()
    times = np.empty(repeats)
    for i in range(repeats):
        t0 = time.perf_counter()
        fn()
        times[i] = time.perf_counter() - t0
    return times


def timed(
    operation: str,
    size: str,
    fn: Callable[[], Any],
    repeats: int,
    *,
    warmup: int = 3,
    baseline: tuple[str, Callable[[], Any], int] | None = None,
    paper: str | None = None,
    note: str = "",
) -> Result:
    """Measure ``fn`` (and optionally a baseline ``(name, fn, repeats)``) and build a :class:`Result`."""
    t = measure(fn, repeats, warmup)
    b_name, b_med, b_p99 = None, None, None
    if baseline is not None:
        b_name, b_fn, b_rep = baseline
        bt = measure(b_fn, b_rep, warmup=1)
        b_med, b_p99 = float(np.median(bt)), float(np.percentile(bt, 99))
    return Result(
        operation, size, float(np.median(t)), float(np.percentile(t, 99)), repeats, b_name, b_med, paper, note, b_p99
    )


def machine() -> dict[str, Any]:
    """What the numbers were measured on (CPU, cores, versions, load average, UTC time)."""
    cpu = platform.processor() or ""
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next((ln.split(":", 1)[1].strip() for ln in f if ln.startswith("model name")), cpu)
    except OSError:
        pass
    try:
        import scipy

        scipy_version = scipy.__version__
    except ImportError:  # pragma: no cover - scipy is a hard dependency
        scipy_version = None
    try:
        load = [round(x, 2) for x in os.getloadavg()]
    except OSError:  # pragma: no cover - not on every platform
        load = None
    return {
        "cpu": cpu,
        "cores": os.cpu_count(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy_version,
        "platform": platform.platform(),
        "load_avg_1_5_15min": load,
        "utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    }


def machine_line(m: dict[str, Any] | None = None) -> str:
    """One line naming the machine, e.g. for the head of the table."""
    m = m or machine()
    load = m.get("load_avg_1_5_15min")
    extra = f", load {load[0]:.2f}" if load else ""
    return (
        f"machine: {m['cpu']}, {m['cores']} cores, Python {m['python']}, numpy {m['numpy']}, "
        f"scipy {m.get('scipy')}{extra}, {m.get('utc', '')}"
    )


def names() -> list[str]:
    """Names of every registered benchmark, in table order (imports the topic modules)."""
    for topic in TOPICS:
        importlib.import_module(f"{__name__}.{topic}")
    return [name for name, _ in _REGISTRY]


def run(
    quick: bool = False, only: list[str] | None = None, progress: Callable[[str], None] | None = None
) -> list[Result]:
    """Run every registered benchmark (or those whose name contains one of ``only``)."""
    names()
    results: list[Result] = []
    for name, fn in _REGISTRY:
        if only and not any(o in name for o in only):
            continue
        if progress:
            progress(name)
        results.extend(fn(quick))
    return results


def _fmt_time(s: float | None) -> str:
    if s is None:
        return "-"
    if s < 1e-3:
        return f"{s * 1e6:.1f} us"
    if s < 1:
        return f"{s * 1e3:.2f} ms"
    return f"{s:.2f} s"


def _fmt_baseline(r: Result) -> str:
    """``name (median)`` or ``name (median, p99 ...)`` of the baseline, ``-`` without one."""
    if not r.baseline:
        return "-"
    p99 = f", p99 {_fmt_time(r.baseline_p99_s)}" if r.baseline_p99_s is not None else ""
    return f"{r.baseline} ({_fmt_time(r.baseline_median_s)}{p99})"


def format_table(results: list[Result]) -> str:
    """A plain-text table: operation, size, median, p99, baseline, ratio, paper."""
    head = ("operation", "size", "median", "p99", "baseline (median, p99)", "ratio", "paper", "note")
    rows = [head]
    for r in results:
        base = _fmt_baseline(r)
        ratio = "-" if r.ratio is None else (f"{r.ratio:.0f}x" if r.ratio >= 100 else f"{r.ratio:.1f}x")
        rows.append(
            (r.operation, r.size, _fmt_time(r.median_s), _fmt_time(r.p99_s), base, ratio, r.paper or "-", r.note)
        )
    widths = [max(len(str(row[i])) for row in rows) for i in range(len(head))]
    lines = ["  ".join(str(c).ljust(w) for c, w in zip(row, widths, strict=True)).rstrip() for row in rows]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def format_markdown(results: list[Result]) -> str:
    """The same table as :func:`format_table` in Markdown (for docs/performance.md)."""
    head = ("operation", "size", "median", "p99", "repeats", "baseline (median, p99)", "ratio", "paper", "note")
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in results:
        base = _fmt_baseline(r)
        ratio = "-" if r.ratio is None else (f"{r.ratio:.0f}x" if r.ratio >= 100 else f"{r.ratio:.1f}x")
        cells = (
            r.operation,
            r.size,
            _fmt_time(r.median_s),
            _fmt_time(r.p99_s),
            str(r.repeats),
            base,
            ratio,
            r.paper or "-",
            r.note or "",
        )
        lines.append("| " + " | ".join(str(c).replace("|", "/") for c in cells) + " |")
    return "\n".join(lines)


def to_json(results: list[Result], quick: bool) -> str:
    """The numbers as JSON: ``{"machine": ..., "quick": ..., "results": [Result.as_dict(), ...]}``."""

    def clean(d: dict[str, Any]) -> dict[str, Any]:  # never NaN in output files: a missing number is null
        return {k: (None if isinstance(v, float) and not np.isfinite(v) else v) for k, v in d.items()}

    return json.dumps(
        {"machine": machine(), "quick": quick, "results": [clean(r.as_dict()) for r in results]},
        indent=2,
        allow_nan=False,
    )
