"""Benchmarks of paper 001: stiffness solves, the Fig. 7 sweep, TV-LIPM plans of 20-2000 steps."""

from __future__ import annotations

import numpy as np
from scipy.optimize import root

from ..planners.tvlip import plan_scenario, sequence_for, solve_boundaries
from ..scenario import load_scenario
from ..stiffness import running_residual, solve_running, stiffness, sweep_running
from . import Result, benchmark, timed

H, TSS, TDS, TF = 0.95, 0.4, 0.15, 0.15


def _scipy_running(h=H, tss=TSS, tf=TF):
    """The paper's method: scipy.optimize.root on eqs. (9)-(11), finite-difference Jacobian."""
    return root(lambda x: running_residual(x[0], x[1], h, tss, tf)[0], [0.8 * np.sqrt(h / 9.81), 0.0])


@benchmark("stiffness")
def bench_stiffness(quick: bool) -> list[Result]:
    n = 20 if quick else 2000
    grid = np.round(np.arange(0.10, 0.395, 0.01), 2)
    S, F = np.meshgrid(grid, grid, indexing="ij")
    _, _, _, it = solve_running(H, TSS, TF)
    sol = _scipy_running()
    out = [
        timed("T_r solve (Newton, analytic Jacobian)", f"1 point, {int(it)} it", lambda: solve_running(H, TSS, TF),
              n, baseline=(f"scipy root hybr ({sol.nfev} fev)", _scipy_running, max(5, n // 10)),
              paper="8 ms, 13 it (scipy root)"),
        timed("all five T (T_w, T_r, v_r, T_t0, T_t1)", "1 timing set", lambda: stiffness(H, TSS, TDS, TF), n),
        timed("T_r sweep, vectorised (Fig. 7)", "900 points", lambda: sweep_running(H, S, F), max(5, n // 20),
              baseline=("900 x scipy root", lambda: [_scipy_running(H, a, b) for a, b in zip(S.ravel(), F.ravel())],
                        1 if quick else 3)),
    ]
    return out


def _wrw(steps_each: tuple[int, int, int], dt: float = 0.001):
    w1, r, w2 = steps_each
    return load_scenario({"gait": [{"gait": "walk", "steps": w1}, {"gait": "run", "steps": r},
                                   {"gait": "walk", "steps": w2}],
                          "timing": {"single_support": TSS, "double_support": TDS, "flight": TF},
                          "foot": {"size": [0.24, 0.14]}, "dt": dt})


@benchmark("tvlip-plan")
def bench_plan(quick: bool) -> list[Result]:
    rep = 5 if quick else 200
    sc20 = load_scenario("paper001-table2-walk-run-walk")
    seq, _ = sequence_for(sc20)
    args = (sc20.height, sc20.gravity, sc20.foot.size, sc20.foot.zmp_margin, sc20.foot.zmp_z)
    out = [
        timed("TV-LIPM plan, walk-run-walk, sampled at 1 ms", f"20 steps, {len(seq.phases)} phases",
              lambda: plan_scenario(sc20), rep, paper="1-2 s, <=100 it"),
        timed("TV-LIPM boundary solve (banded KKT)", f"20 steps, {len(seq.phases)} phases",
              lambda: solve_boundaries(seq, *args), rep,
              baseline=("dense KKT LU, same problem", lambda: solve_boundaries(seq, *args, dense=True),
                        3 if quick else 20)),
    ]
    base = None
    for n in (20, 200, 2000):
        third = n // 4
        sc = _wrw((third, n - 2 * third, third))
        seq_n, _ = sequence_for(sc)
        r = timed("TV-LIPM boundary solve (banded KKT)", f"{n} steps, {len(seq_n.phases)} phases",
                  lambda seq_n=seq_n, sc=sc: solve_boundaries(seq_n, sc.height, sc.gravity, sc.foot.size,
                                                              sc.foot.zmp_margin, sc.foot.zmp_z),
                  max(3, rep // (1 + n // 100)))
        per = r.median_s / n
        base = base or per
        out.append(Result(r.operation, r.size, r.median_s, r.p99_s, r.repeats,
                          note=f"{per * 1e6:.1f} us/step ({per / base:.2f}x the 20-step cost per step)"))
    return out
