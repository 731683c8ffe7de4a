"""Benchmarks of paper 001: stiffness solves, the Fig. 7 sweep, TV-LIPM plans of 20-2000 steps, and
the sampling of a plan (the vectorised closed forms against the per-sample reference path kept here,
:func:`reference_sample`, which the tests also use as an independent oracle)."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from scipy.optimize import root

from gaitshift.bench import Result, benchmark, timed
from gaitshift.gait.sequence import GaitSequence
from gaitshift.gait.swing import swing_path
from gaitshift.models.stiffness import running_residual, solve_running, stiffness, sweep_running
from gaitshift.models.tvlip import flight_state, support_state
from gaitshift.planners.tvlip.kkt import BoundaryPlan
from gaitshift.planners.tvlip.planner import plan_scenario, plan_sequence, sequence_for, solve_boundaries
from gaitshift.planners.tvlip.sampling import sample
from gaitshift.scenario import load_scenario
from gaitshift.scenario.tvlip import TvlipScenario
from gaitshift.trajectory.contract import FLIGHT, LEFT, RIGHT

H, TSS, TDS, TF = 0.95, 0.4, 0.15, 0.15
WRW = "paper001-table2-walk-run-walk"


def _scipy_running(h: float = H, tss: float = TSS, tf: float = TF) -> Any:
    """The paper's method: scipy.optimize.root on eqs. (9)-(11), finite-difference Jacobian."""
    return root(lambda x: running_residual(x[0], x[1], h, tss, tf)[0], [0.8 * np.sqrt(h / 9.81), 0.0])


# ============================================================================ reference sampling
def reference_evaluate(
    seq: GaitSequence, bp: BoundaryPlan, k: np.ndarray, s: np.ndarray, g: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """CoM position, velocity, acceleration and ZMP (each (len(k), 3)) at time ``s`` into phase ``k``
    by :func:`~gaitshift.models.tvlip.support_state` (eqs. (1)-(4)) and
    :func:`~gaitshift.models.tvlip.flight_state` (eqs. (5)-(6)) per sample (the planner's sampling
    before issue 10)."""
    n = len(k)
    sup = seq.kind[k] != FLIGHT
    p, v, a = np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3))
    c = np.full((n, 3), np.nan)
    ks = k[sup]
    p[sup], v[sup], a[sup], c[sup] = support_state(
        bp.p[ks], bp.v[ks], bp.c[ks], bp.c[ks + 1], seq.stiffness[ks], seq.duration[ks], s[sup], g
    )
    kf = k[~sup]
    p[~sup], v[~sup], a[~sup] = flight_state(bp.p[kf], bp.v[kf], s[~sup], g)
    return p, v, a, c


def reference_feet(seq: GaitSequence, t: np.ndarray, k: np.ndarray, swing_height: float) -> np.ndarray:
    """Sole centres (N, 2, 3) by :func:`~gaitshift.gait.swing.swing_path` per swing sample (the
    planner's sampling before issue 10)."""
    on = seq.on
    fs = seq.footstep_array
    tb = seq.boundary_times
    K = len(on)
    feet = np.empty((len(t), 2, 3))
    for side in (LEFT, RIGHT):
        idx = on[:, side]
        last = np.maximum.accumulate(np.where(idx >= 0, np.arange(K), -1))
        nxt = np.where(idx >= 0, np.arange(K), K)
        nxt = np.minimum.accumulate(nxt[::-1])[::-1]
        from_fs = idx[np.maximum(last, 0)]
        to_fs = idx[np.minimum(nxt, K - 1)]
        t_lift = tb[np.maximum(last, 0) + 1]
        t_land = tb[np.minimum(nxt, K - 1)]
        ph_in = idx[k] >= 0
        pos = np.empty((len(t), 3))
        pos[ph_in] = fs[idx[k][ph_in], :3]
        sw = ~ph_in
        if np.any(sw):
            kk = k[sw]
            u = (t[sw] - t_lift[kk]) / (t_land[kk] - t_lift[kk])
            pos[sw] = swing_path(fs[from_fs[kk], :3], fs[to_fs[kk], :3], swing_height, u)
        feet[:, side] = pos
    return feet


def reference_sample(
    seq: GaitSequence, bp: BoundaryPlan, g: float, dt: float, swing_height: float
) -> dict[str, np.ndarray]:
    """The contract arrays of :func:`gaitshift.planners.tvlip.sampling.sample`, computed per sample by
    the reference path (:func:`reference_evaluate`, :func:`reference_feet`)."""
    tb = seq.boundary_times
    n = math.floor(tb[-1] / dt + 1e-9) + 1
    t = np.arange(n) * dt
    k = np.clip(np.searchsorted(tb, t + 1e-9 * dt, side="right") - 1, 0, len(seq.phases) - 1)
    s = np.maximum(t - tb[k], 0.0)
    kinds, T = seq.kind[k], seq.stiffness[k]
    pos, vel, acc, zmp = reference_evaluate(seq, bp, k, s, g)
    return {
        "t": t,
        "com_pos": pos,
        "com_vel": vel,
        "com_acc": acc,
        "zmp": zmp,
        "phase": kinds.astype(np.int8),
        "stiffness": np.where(kinds != FLIGHT, T, np.nan),
        "command_vel": np.full((n, 2), np.nan),
        "contact": seq.on[k] >= 0,
        "foot_pos": reference_feet(seq, t, k, swing_height),
    }


@benchmark("stiffness")
def bench_stiffness(quick: bool) -> list[Result]:
    n = 20 if quick else 2000
    grid = np.round(np.arange(0.10, 0.395, 0.01), 2)
    S, F = np.meshgrid(grid, grid, indexing="ij")
    _, _, _, it = solve_running(H, TSS, TF)
    sol = _scipy_running()
    out = [
        timed(
            "T_r solve (Newton, analytic Jacobian)",
            f"1 point, {int(it)} it",
            lambda: solve_running(H, TSS, TF),
            n,
            baseline=(f"scipy root hybr ({sol.nfev} fev)", _scipy_running, max(5, n // 10)),
            paper="8 ms, 13 it (scipy root)",
        ),
        timed("all five T (T_w, T_r, v_r, T_t0, T_t1)", "1 timing set", lambda: stiffness(H, TSS, TDS, TF), n),
        timed(
            "T_r sweep, vectorised (Fig. 7)",
            "900 points",
            lambda: sweep_running(H, S, F),
            max(5, n // 20),
            baseline=(
                "900 x scipy root",
                lambda: [_scipy_running(H, a, b) for a, b in zip(S.ravel(), F.ravel(), strict=True)],
                1 if quick else 3,
            ),
        ),
    ]
    return out


def wrw_scenario(steps_each: tuple[int, int, int], dt: float = 0.001) -> TvlipScenario:
    """A walk-run-walk scenario with ``steps_each`` = (walk, run, walk) steps, sampled at ``dt``."""
    w1, r, w2 = steps_each
    sc: TvlipScenario = load_scenario(
        {
            "gait": [{"gait": "walk", "steps": w1}, {"gait": "run", "steps": r}, {"gait": "walk", "steps": w2}],
            "timing": {"single_support": TSS, "double_support": TDS, "flight": TF},
            "foot": {"size": [0.24, 0.14]},
            "dt": dt,
        }
    )
    return sc


def _solve_once(seq: GaitSequence, sc: TvlipScenario) -> Callable[[], BoundaryPlan]:
    """The boundary solve of ``seq`` with the scenario's parameters, as a timing closure."""
    return lambda: solve_boundaries(seq, sc.height, sc.gravity, sc.foot.size, sc.foot.zmp_margin, sc.foot.zmp_z)


@benchmark("tvlip-plan")
def bench_plan(quick: bool) -> list[Result]:
    rep = 5 if quick else 200
    sc20 = load_scenario(WRW)
    seq, _ = sequence_for(sc20)
    args = (sc20.height, sc20.gravity, sc20.foot.size, sc20.foot.zmp_margin, sc20.foot.zmp_z)
    out = [
        timed(
            "TV-LIPM plan, walk-run-walk, sampled at 1 ms",
            f"20 steps, {len(seq.phases)} phases",
            lambda: plan_scenario(sc20),
            rep,
            paper="1-2 s, <=100 it",
        ),
        timed(
            "TV-LIPM boundary solve (banded KKT)",
            f"20 steps, {len(seq.phases)} phases",
            lambda: solve_boundaries(seq, *args),
            rep,
            baseline=(
                "dense KKT LU, same problem",
                lambda: solve_boundaries(seq, *args, dense=True),
                3 if quick else 20,
            ),
        ),
    ]
    base = None
    for n in (20, 200, 2000):
        third = n // 4
        sc = wrw_scenario((third, n - 2 * third, third))
        seq_n, _ = sequence_for(sc)
        r = timed(
            "TV-LIPM boundary solve (banded KKT)",
            f"{n} steps, {len(seq_n.phases)} phases",
            _solve_once(seq_n, sc),
            max(3, rep // (1 + n // 100)),
        )
        per = r.median_s / n
        base = base or per
        out.append(
            Result(
                r.operation,
                r.size,
                r.median_s,
                r.p99_s,
                r.repeats,
                note=f"{per * 1e6:.1f} us/step ({per / base:.2f}x the 20-step cost per step)",
            )
        )
    return out


@benchmark("tvlip-sample")
def bench_sample(quick: bool) -> list[Result]:
    """Sampling the 20-step walk-run-walk plan at 1 ms: the vectorised closed forms against the
    per-sample reference path (the sampling before issue 10), and the whole solve + sample."""
    rep = 5 if quick else 300
    sc = load_scenario(WRW)
    seq, _ = sequence_for(sc)
    args = (sc.height, sc.gravity, sc.foot.size, sc.foot.zmp_margin, sc.foot.zmp_z)
    bp = solve_boundaries(seq, *args)
    n = len(sample(seq, bp, sc.gravity, sc.dt, sc.swing_height)["t"])
    size = f"20 steps, {len(seq.phases)} phases, {n} samples"
    return [
        timed(
            "sample 20-step walk-run-walk at 1 ms",
            size,
            lambda: sample(seq, bp, sc.gravity, sc.dt, sc.swing_height),
            rep,
            baseline=(
                "per-sample reference path",
                lambda: reference_sample(seq, bp, sc.gravity, sc.dt, sc.swing_height),
                3 if quick else 60,
            ),
            note="CoM, ZMP and feet; goal: 5x the reference",
        ),
        timed(
            "solve + sample 20-step walk-run-walk at 1 ms",
            size,
            lambda: plan_sequence(seq, *args, sc.dt, sc.swing_height),
            rep,
            baseline=(
                "solve + reference sampling",
                lambda: reference_sample(seq, solve_boundaries(seq, *args), sc.gravity, sc.dt, sc.swing_height),
                3 if quick else 60,
            ),
            note="goal <= 2 ms",
        ),
    ]
