#!/usr/bin/env python
"""Run the full gaitshift benchmark suite and write benchmarks/results.json (+ results.md).

Usage (from the repository root)::

    .venv/bin/python benchmarks/run_full.py            # full run, about 1-5 minutes
    .venv/bin/python benchmarks/run_full.py --quick    # smoke run: every benchmark once or twice
    .venv/bin/python benchmarks/run_full.py --only slip --out /tmp/slip.json

The table is printed as it is produced by ``gaitshift bench``; the JSON holds the machine, the
per-row numbers (seconds) and the total wall time of the run. Output files are written atomically.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from gaitshift import bench
from gaitshift.common.atomic import atomic_path

HERE = Path(__file__).resolve().parent


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="smoke run (checks that every benchmark runs)")
    ap.add_argument("--only", action="append", help="run only benchmarks whose name contains this")
    ap.add_argument("--out", type=Path, default=HERE / "results.json", help="JSON output file")
    args = ap.parse_args(argv)

    print(bench.machine_line(), flush=True)
    t0 = time.perf_counter()
    results = bench.run(
        quick=args.quick, only=args.only, progress=lambda n: print(f"  running {n} ...", file=sys.stderr, flush=True)
    )
    wall = time.perf_counter() - t0
    print(bench.format_table(results))
    print(f"total wall time {wall:.1f} s")

    data = json.loads(bench.to_json(results, args.quick))
    data["total_wall_s"] = wall
    with atomic_path(args.out) as tmp:
        tmp.write_text(json.dumps(data, indent=2, allow_nan=False))
    md = args.out.with_suffix(".md")
    with atomic_path(md) as tmp:
        tmp.write_text(
            bench.machine_line(data["machine"]) + f", total {wall:.1f} s\n\n" + bench.format_markdown(results) + "\n"
        )
    print(f"wrote {args.out} and {md}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
