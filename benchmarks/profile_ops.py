#!/usr/bin/env python
"""Where the time goes: cProfile of the main operations (used for docs/performance.md).

    .venv/bin/python benchmarks/profile_ops.py            # all operations, top 12 functions each
    .venv/bin/python benchmarks/profile_ops.py slip -n 20

Operations: ``stiffness`` (one T_r solve, repeated), ``sweep`` (Fig. 7 grid of 900 T_r), ``plan``
(TV-LIPM plan of the built-in 20-step walk-run-walk scenario, sampled at 1 ms), ``solve`` and
``sample`` (its boundary solve and its sampling alone), ``boundaries2000`` (the planner's boundary
solve alone for 2000 steps), ``slip`` (periodic 3D-SLIP search).
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
    from gaitshift.models.stiffness import solve_running, sweep_running

    grid = np.round(np.arange(0.10, 0.395, 0.01), 2)
    S, F = np.meshgrid(grid, grid, indexing="ij")
    ops = {
        "stiffness": (lambda: solve_running(0.95, 0.4, 0.15), 300),
        "sweep": (lambda: sweep_running(0.95, S, F), 20),
        "slip": (lambda: periodic_half_cycle(3.5), 5),
    }
    import gaitshift
    from gaitshift.bench.tvlip import wrw_scenario
    from gaitshift.planners.tvlip.planner import plan_scenario, sequence_for, solve_boundaries
    from gaitshift.planners.tvlip.sampling import sample

    sc = gaitshift.load_scenario("paper001-table2-walk-run-walk")
    ops["plan"] = (lambda: plan_scenario(sc), 20)
    seq20, _ = sequence_for(sc)
    args = (sc.height, sc.gravity, sc.foot.size, sc.foot.zmp_margin, sc.foot.zmp_z)
    bp20 = solve_boundaries(seq20, *args)
    ops["solve"] = (lambda: solve_boundaries(seq20, *args), 100)
    ops["sample"] = (lambda: sample(seq20, bp20, sc.gravity, sc.dt, sc.swing_height), 100)
    big = wrw_scenario((500, 1000, 500))
    seq, _ = sequence_for(big)
    ops["boundaries2000"] = (
        lambda: solve_boundaries(seq, big.height, big.gravity, big.foot.size, big.foot.zmp_margin, big.foot.zmp_z),
        5,
    )
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
