#!/usr/bin/env python
"""Where the time goes: cProfile of the main operations (used for docs/performance.md).

    .venv/bin/python benchmarks/profile_ops.py            # all operations, top 12 functions each
    .venv/bin/python benchmarks/profile_ops.py slip -n 20

Operations: ``stiffness`` (one T_r solve, repeated), ``sweep`` (Fig. 7 grid of 900 T_r), ``plan``
(TV-LIPM plan of the built-in 20-step walk-run-walk scenario, sampled at 1 ms), ``boundaries2000``
(the planner's boundary solve alone for 2000 steps), ``slip`` (periodic 3D-SLIP search).
Each profile prints the wall time per call without the profiler first (cProfile slows Python-heavy
code down by up to about 2x), then the functions sorted by their own time (tottime).
"""

from __future__ import annotations

import argparse
import cProfile
import io
import pstats
import time

import numpy as np


def _ops():
    from gaitshift.models.slip import periodic_half_cycle
    from gaitshift.stiffness import solve_running, sweep_running

    grid = np.round(np.arange(0.10, 0.395, 0.01), 2)
    S, F = np.meshgrid(grid, grid, indexing="ij")
    ops = {
        "stiffness": (lambda: solve_running(0.95, 0.4, 0.15), 300),
        "sweep": (lambda: sweep_running(0.95, S, F), 20),
        "slip": (lambda: periodic_half_cycle(3.5), 5),
    }
    try:
        import gaitshift
        from gaitshift.planners.tvlip import plan_scenario

        sc = gaitshift.load_scenario("paper001-table2-walk-run-walk")
        ops["plan"] = (lambda: plan_scenario(sc), 20)
        from gaitshift.bench.tvlip import _wrw
        from gaitshift.planners.tvlip import sequence_for, solve_boundaries

        big = _wrw((500, 1000, 500))
        seq, _ = sequence_for(big)
        ops["boundaries2000"] = (lambda: solve_boundaries(seq, big.height, big.gravity, big.foot.size,
                                                          big.foot.zmp_margin, big.foot.zmp_z), 5)
    except Exception as exc:  # the planner is another topic; profile what exists
        print(f"(plan skipped: {exc})")
    return ops


def profile(name: str, fn, repeats: int, top: int) -> str:
    fn()
    t0 = time.perf_counter()
    for _ in range(repeats):
        fn()
    per = (time.perf_counter() - t0) / repeats
    pr = cProfile.Profile()
    pr.enable()
    for _ in range(repeats):
        fn()
    pr.disable()
    buf = io.StringIO()
    st = pstats.Stats(pr, stream=buf).strip_dirs().sort_stats("tottime")
    st.print_stats(top)
    body = "\n".join(ln for ln in buf.getvalue().splitlines() if ln.strip())
    return f"== {name}: {per * 1e3:.3f} ms per call without profiler ({repeats} calls profiled)\n{body}\n"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("ops", nargs="*")
    ap.add_argument("-n", type=int, default=12, help="functions to show")
    args = ap.parse_args(argv)
    ops = _ops()
    for name in args.ops or list(ops):
        fn, rep = ops[name]
        print(profile(name, fn, rep, args.n))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
