"""Benchmarks of the whole-body layer: IK time per sample and for a 10 s plan at 500 Hz (G1)."""

from __future__ import annotations

import numpy as np

from . import Result, benchmark, timed

TARGET = "target: 10 s plan at 500 Hz in < 10 s"


def _plan_10s(rate: float = 500.0):
    import gaitshift
    from ..robot.ik import subsample
    from ..trajectory import Trajectory

    traj = subsample(gaitshift.plan(gaitshift.load_scenario("g1-walk-run-walk")), rate)
    keep = traj.t <= traj.t[0] + 10.0 - 0.5 / rate
    arrays = {k: (v[keep] if np.ndim(v) and len(v) == len(traj) else v) for k, v in traj.arrays().items()}
    arrays["footsteps"], arrays["footstep_side"] = traj.footsteps, traj.footstep_side
    return Trajectory.from_arrays(arrays, dict(traj.meta))


@benchmark("robot")
def bench_robot(quick: bool) -> list[Result]:
    from ..robot.ik import IKSettings, WholeBodyIK

    traj = _plan_10s()
    n = len(traj)
    ik = WholeBodyIK("g1")
    cold = WholeBodyIK("g1", IKSettings(extrapolate=False))
    # per sample: one full pass each; the first sample (from standing) is excluded
    ik.solve(traj)
    st, it = ik.last_sample_times[1:], ik.last_iterations[1:]
    cold.solve(traj)
    cst, cit = cold.last_sample_times[1:], cold.last_iterations[1:]
    rows = [Result("whole-body IK per sample (G1, mink+daqp)", f"{n} samples, 500 Hz",
                   float(np.median(st)), float(np.percentile(st, 99)), len(st),
                   "warm start at q_{k-1}, no extrapolation", float(np.median(cst)), None,
                   f"iterations/sample median {np.median(it):.0f}, max {it.max()} "
                   f"(baseline {np.median(cit):.0f}, max {cit.max()})")]
    repeats = 1 if quick else 3
    rows.append(timed("whole-body motion, 10 s walk-run-walk plan (G1)", f"{n} samples, 500 Hz",
                      lambda: ik.solve(traj), repeats, warmup=0, paper=TARGET))
    return rows
