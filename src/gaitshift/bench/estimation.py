"""Speed of the state estimator (docs/estimation.md, "Measured cost"), baselines measured in the same run.

* ``G1 estimator tick (StateEstimator.step)``: contact detection, joint filter, kinematics, base
  filter, CoM and slip (the compiled tick for the InEKFs), timed with ``time.perf_counter`` around
  each tick of the recorded G1 sway (:mod:`gaitshift.bench.g1sway`, 6 s = 3000 ticks of 2 ms); the
  baseline is the same estimator with leg odometry (the baseline filter, on the Python path) over the
  very same readings. The InEKFs correct every ``FilterTuning().correct_every`` ticks: the median is
  a tick without a correction; the note gives the median of the correction ticks.
* ``SO(3) exp as a 3 x 3 matrix``: the in-place MuJoCo quaternion calls the filters use, and the
  closed-form Rodrigues in ``math``, each against mink's ``SO3.exp(w).as_matrix()``.

The full report (several trials with the load average, and the accuracy tables) is
``benchmarks/estimation.py``.
"""

from __future__ import annotations

import time
import timeit
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from gaitshift.bench import Result, benchmark, measure

if TYPE_CHECKING:
    from gaitshift.bench.g1sway import RecordedRun

#: a filter the compiled tick covers: one discarded run of it first, so that no measured run pays
#: numba's cache load (0.2 s) or compilation (7 s on a cold cache) in its first tick
DEFAULT_COMPILED_FILTER = "inekf"
#: the filters timed against the baseline filter
TIMED_FILTERS = ("inekf", "inekf-flat")
BASELINE_FILTER = "leg-odometry"
#: calls per timed sample of an SO(3) exponential (one call is about a microsecond)
EXP_BATCH = 100


def lie_routes() -> dict[str, Callable[[], Any]]:
    """Three routes to one SO(3) exponential as a 3 x 3 matrix, on a small rotation vector."""
    import mujoco
    from mink.lie import SO3

    from gaitshift.control.estimation.lie import rodrigues

    w = np.array([0.3e-3, -0.2e-3, 0.5e-3])
    quat, mat = np.array([1.0, 0.0, 0.0, 0.0]), np.empty(9)

    def mujoco_in_place() -> None:
        mujoco.mju_quatIntegrate(quat, w, 1.0)
        mujoco.mju_quat2Mat(mat, quat)

    return {
        "mink SO3.exp(w).as_matrix()": lambda: SO3.exp(w).as_matrix(),
        "Rodrigues in math": lambda: rodrigues(w),
        "MuJoCo in place (mju_quatIntegrate + mju_quat2Mat)": mujoco_in_place,
    }


def lie_costs(n: int = 20000) -> dict[str, float]:
    """Best-of-5 mean cost, us, of one SO(3) exponential as a 3 x 3 matrix, three routes."""
    return {k: min(timeit.repeat(f, number=n, repeat=5)) / n * 1e6 for k, f in lie_routes().items()}


def tick_costs(robot: Any, run: RecordedRun, name: str, profile: str) -> np.ndarray:
    """Per-tick cost, us, of the estimator over the recorded run."""
    from gaitshift.control.estimation.estimator import StateEstimator

    est = StateEstimator.from_robot(robot, run.dt, filter=name, noise=profile)
    est.reset(run.qpos0, run.qvel0)
    out = np.empty(len(run.imu))
    clock = time.perf_counter
    for k in range(len(run.imu)):
        t0 = clock()
        est.step(run.imu[k], run.joints[k], run.forces[k])
        out[k] = clock() - t0
    return out * 1e6


def correction_ticks(n: int, every: int) -> np.ndarray:
    """(n,) flags of the ticks that correct: ticks every, 2 every, ... (1-based)."""
    correcting = np.zeros(n, dtype=bool)
    correcting[every - 1 :: every] = True
    return correcting


def _tick_rows(quick: bool) -> list[Result]:
    from gaitshift.bench.g1sway import record_g1_sway
    from gaitshift.control.estimation.tuning import FilterTuning
    from gaitshift.robots import load_robot

    robot = load_robot("g1")
    run = record_g1_sway(robot, duration=0.2 if quick else 6.0, profile="typical", seed=0)
    n = len(run.imu)
    tick_costs(robot, run, DEFAULT_COMPILED_FILTER, "typical")  # discarded: loads (or compiles) the kernels
    every = FilterTuning().correct_every
    rows = []
    for name in TIMED_FILTERS:
        costs = tick_costs(robot, run, name, "typical") * 1e-6
        base = tick_costs(robot, run, BASELINE_FILTER, "typical") * 1e-6
        corr = float(np.median(costs[correction_ticks(n, every)]))
        note = (
            f"correction every {every} ticks: median of the correction ticks {corr * 1e6:.1f} us; "
            f"{np.median(costs) / run.dt * 100:.1f} % of the {run.dt * 1e3:.0f} ms tick"
        )
        rows.append(
            Result(
                "G1 estimator tick (StateEstimator.step)",
                f"{name}, {n} ticks of the recorded sway",
                float(np.median(costs)),
                float(np.percentile(costs, 99)),
                n,
                f"{BASELINE_FILTER} tick, same readings",
                float(np.median(base)),
                "-",
                note,
                float(np.percentile(base, 99)),
            )
        )
    return rows


def _exp_rows(quick: bool) -> list[Result]:
    routes = lie_routes()
    base_name = "mink SO3.exp(w).as_matrix()"
    reps = 20 if quick else 2000

    def batch(f: Callable[[], Any]) -> Callable[[], None]:
        def run() -> None:
            for _ in range(EXP_BATCH):
                f()

        return run

    rows = []
    for name in ("MuJoCo in place (mju_quatIntegrate + mju_quat2Mat)", "Rodrigues in math"):
        t = measure(batch(routes[name]), reps) / EXP_BATCH
        b = measure(batch(routes[base_name]), reps, warmup=1) / EXP_BATCH
        note = f"per call: each sample times {EXP_BATCH} calls"
        rows.append(
            Result(
                "SO(3) exp as a 3 x 3 matrix",
                name,
                float(np.median(t)),
                float(np.percentile(t, 99)),
                reps,
                base_name,
                float(np.median(b)),
                "-",
                note,
                float(np.percentile(b, 99)),
            )
        )
    return rows


@benchmark("estimation")
def bench_estimation(quick: bool) -> list[Result]:
    return _tick_rows(quick) + _exp_rows(quick)
