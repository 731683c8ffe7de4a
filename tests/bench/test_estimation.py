"""The estimator benchmark measures what it says: the ticks it reports as correction ticks are the
ticks where the InEKF's covariance changes (its correction schedule), and its smoke run gives every
row a median, a p99 and a baseline measured in the same run (times are never judged)."""

from __future__ import annotations

import json

import numpy as np

from gaitshift import bench
from gaitshift.bench.estimation import correction_ticks
from gaitshift.bench.g1sway import record_g1_sway
from gaitshift.control.estimation import FilterTuning, StateEstimator
from gaitshift.robots import load_robot


def test_correction_ticks_are_where_the_inekf_covariance_changes():
    g1 = load_robot("g1")
    run = record_g1_sway(g1, duration=0.1, profile="typical", seed=0)
    est = StateEstimator.from_robot(g1, run.dt, filter="inekf", noise="typical")
    est.reset(run.qpos0, run.qvel0)
    trace = [float(est.step(run.imu[k], run.joints[k], run.forces[k]).cov_trace) for k in range(len(run.imu))]
    changed = np.diff(np.array(trace), prepend=np.nan) != 0.0
    expected = correction_ticks(len(run.imu), FilterTuning().correct_every)
    np.testing.assert_array_equal(changed[1:], expected[1:])


def test_quick_run_gives_every_row_median_p99_and_a_baseline():
    rows = bench.run(quick=True, only=["estimation"])
    ops = [r.operation for r in rows]
    assert ops.count("G1 estimator tick (StateEstimator.step)") == 2
    assert ops.count("SO(3) exp as a 3 x 3 matrix") == 2
    for r in rows:
        assert np.isfinite(r.median_s) and np.isfinite(r.p99_s) and 0 < r.median_s <= r.p99_s
        assert r.baseline is not None and r.baseline_median_s is not None and r.baseline_p99_s is not None
        assert np.isfinite(r.baseline_median_s) and r.baseline_median_s <= r.baseline_p99_s
    data = json.loads(bench.to_json(rows, quick=True))
    assert data["quick"] is True and len(data["results"]) == len(rows)
