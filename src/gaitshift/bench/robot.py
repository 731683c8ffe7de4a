"""Benchmarks of the whole-body layer: IK time per sample and for a 10 s plan at 500 Hz (G1; the smoke run
``--quick``: its first 2 s)."""

from __future__ import annotations

from typing import Any

import numpy as np

from gaitshift.bench import Result, benchmark, timed

TARGET = "target: 10 s plan at 500 Hz in < 10 s"


def _plan(seconds: float, rate: float = 500.0) -> Any:
    import gaitshift
    from gaitshift.trajectory.contract import Trajectory
    from gaitshift.wholebody.joints import subsample

    traj = subsample(gaitshift.plan(gaitshift.load_scenario("g1-walk-run-walk")), rate)
    keep = traj.t <= traj.t[0] + seconds - 0.5 / rate
    arrays = {k: (v[keep] if np.ndim(v) and len(v) == len(traj) else v) for k, v in traj.arrays().items()}
    arrays["footsteps"], arrays["footstep_side"] = traj.footsteps, traj.footstep_side
    return Trajectory.from_arrays(arrays, dict(traj.meta))


@benchmark("robot")
def bench_robot(quick: bool) -> list[Result]:
    from gaitshift.wholebody.ik import IKSettings, WholeBodyIK

    seconds = 2.0 if quick else 10.0
    traj = _plan(seconds)
    n = len(traj)
    ik = WholeBodyIK("g1")
    cold = WholeBodyIK("g1", IKSettings(extrapolate=False))
    # per sample: full passes, the two variants alternating so that machine load hits both alike;
    # the first sample of each pass (from the standing pose, up to 200 iterations) is excluded
    passes = 1 if quick else 3
    runs: dict[str, list[np.ndarray]] = {"st": [], "it": [], "cst": [], "cit": []}
    for _ in range(passes):
        ik.solve(traj)
        runs["st"].append(ik.last_sample_times[1:])
        runs["it"].append(ik.last_iterations[1:])
        cold.solve(traj)
        runs["cst"].append(cold.last_sample_times[1:])
        runs["cit"].append(cold.last_iterations[1:])
    st, it, cst, cit = (np.concatenate(runs[k]) for k in ("st", "it", "cst", "cit"))
    rows = [
        Result(
            "whole-body IK per sample (G1, mink+daqp)",
            f"{n} samples, 500 Hz",
            float(np.median(st)),
            float(np.percentile(st, 99)),
            len(st),
            "warm start at q_{k-1}, no extrapolation",
            float(np.median(cst)),
            None,
            f"iterations/sample mean {it.mean():.2f}, max {it.max()} (baseline mean {cit.mean():.2f}, max {cit.max()})",
        )
    ]
    repeats = 1 if quick else 3
    rows.append(
        timed(
            f"whole-body motion, {seconds:g} s walk-run-walk plan (G1)",
            f"{n} samples, 500 Hz",
            lambda: ik.solve(traj),
            repeats,
            warmup=0,
            paper=TARGET,
        )
    )
    return rows
