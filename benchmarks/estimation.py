"""Measured cost and accuracy of the estimator: the numbers of docs/estimation.md.

    .venv/bin/python benchmarks/estimation.py [--trials 5] [--json out.json] [--skip-accuracy]

(``gaitshift bench --only estimation`` gives the median and p99 of one run against its baselines.)

* cost: one :class:`StateEstimator` tick (contact detection, joint filter, kinematics, base filter,
  CoM, slip; the compiled tick for the InEKFs) on the recorded G1 sway, timed with
  ``time.perf_counter`` per tick over every tick of the run (3000), median and p99, in ``trials``
  separate runs (the machine is shared: the report gives the best and the worst trial, the 1-minute
  load average, and a reference numpy timing);
* SO(3) exponential routes: mink's ``SO3.exp(w).as_matrix()``, the closed-form Rodrigues in ``math``
  and the in-place MuJoCo quaternion calls the filters use;
* accuracy: RMS errors on the synthetic walk (5 seeds, 8 s) and on the recorded G1 sway (3 seeds,
  6 s), for the ``typical`` and ``rl-peer`` profiles and every filter.
"""

from __future__ import annotations

import argparse
import json
import os
import timeit
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from gaitshift.bench.estimation import DEFAULT_COMPILED_FILTER, correction_ticks, lie_costs, tick_costs
from gaitshift.bench.g1sway import RecordedRun, record_g1_sway
from gaitshift.bench.synthetic import synthetic_readings, synthetic_walk
from gaitshift.control.estimation.estimator import StateEstimator
from gaitshift.control.estimation.filters import FILTERS, make_filter
from gaitshift.control.estimation.tuning import FilterTuning

PROFILES = ("typical", "rl-peer")


def reference_us() -> float:
    """Time of a (3,) + (3,) numpy addition, us (the machine's current speed for small arrays)."""
    a = np.ones(3)
    return min(timeit.repeat(lambda: a + a, number=20000, repeat=5)) / 20000 * 1e6


def _rms(err: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.sum(np.square(err), axis=-1))))


def synthetic_accuracy(name: str, profile: str, seeds: int = 5, duration: float = 8.0) -> dict[str, float]:
    """Mean over seeds of the RMS errors after 2 s (tilt, yaw, velocity) and the drift at the end."""
    walk = synthetic_walk(duration)
    settled = slice(round(2.0 / walk.dt), None)
    rows = []
    for seed in range(seeds):
        imu, feet, _ = synthetic_readings(walk, profile, seed=seed)
        f = make_filter(name, FilterTuning.from_profile(profile, walk.dt))
        f.reset(walk.rot[0], walk.pos[0], walk.vel[0])
        states = [f.step(imu[k], feet[k], walk.contact[k], walk.dt) for k in range(1, walk.t.size)]
        rot = np.array([s.rot for s in states])
        err = (Rotation.from_matrix(walk.rot[1:]) * Rotation.from_matrix(rot).inv()).as_rotvec()[settled]
        vel = np.array([s.vel for s in states])[settled] - walk.vel[1:][settled]
        pos = states[-1].pos - walk.pos[-1]
        rows.append([_rms(err[:, 0:2]), abs(err[-1, 2]), _rms(vel), float(np.linalg.norm(pos)), abs(pos[2])])
    keys = ("tilt_rad", "yaw_end_rad", "vel_mps", "pos_end_m", "height_end_m")
    return dict(zip(keys, np.mean(rows, axis=0).tolist(), strict=True))


def g1_accuracy(robot: Any, runs: list[RecordedRun], name: str, profile: str) -> dict[str, float]:
    """Mean over the recorded runs of the RMS errors (tilt, velocities, CoM) and the end drifts."""
    rows = []
    for run in runs:
        est = StateEstimator.from_robot(robot, run.dt, filter=name, noise=profile)
        est.reset(run.qpos0, run.qvel0)
        states = [est.step(run.imu[k], run.joints[k], run.forces[k]) for k in range(len(run.imu))]
        quat = np.array([s.base_quat for s in states])
        truth = Rotation.from_quat(run.qpos[:, 3:7], scalar_first=True)
        err = (truth * Rotation.from_quat(quat, scalar_first=True).inv()).as_rotvec()
        contact = np.array([s.contact for s in states])
        rows.append(
            [
                _rms(err[:, 0:2]),
                abs(err[-1, 2]),
                _rms(np.array([s.base_vel for s in states]) - run.qvel[:, 0:3]),
                float(np.linalg.norm(states[-1].base_pos - run.qpos[-1, 0:3])),
                _rms(np.array([s.com for s in states]) - run.com),
                _rms(np.array([s.com_vel for s in states]) - run.com_vel),
                float(np.mean(contact == run.contact)),
                float(np.mean([s.slip.any() for s in states])),
            ]
        )
    keys = ("tilt_rad", "yaw_end_rad", "vel_mps", "pos_end_m", "com_m", "com_vel_mps", "contact_agree", "slip_frac")
    return dict(zip(keys, np.mean(rows, axis=0).tolist(), strict=True))


def main(argv: list[str] | None = None) -> dict[str, Any]:
    """Run every measurement, print a summary, and return (and optionally save) the numbers."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=5)
    parser.add_argument("--json", default=None)
    parser.add_argument("--skip-accuracy", action="store_true")
    args = parser.parse_args(argv)
    from gaitshift.robots import load_robot

    robot = load_robot("g1")
    report: dict[str, Any] = {"lie_us": lie_costs(), "cost_us": {}, "synthetic": {}, "g1": {}}
    run = record_g1_sway(robot, duration=6.0, profile="typical", seed=0)
    tick_costs(robot, run, DEFAULT_COMPILED_FILTER, "typical")  # discarded: loads (or compiles) the kernels
    for name in FILTERS:
        trials: list[dict[str, float | None]] = []
        for _ in range(args.trials):
            load, ref = os.getloadavg()[0], reference_us()
            costs = tick_costs(robot, run, name, "typical")
            every = FilterTuning().correct_every if name.startswith("inekf") else 1
            correcting = correction_ticks(costs.size, every)
            trials.append(
                {
                    "median": float(np.median(costs)),
                    "mean": float(np.mean(costs)),
                    "p99": float(np.percentile(costs, 99)),
                    "median_correction_ticks": float(np.median(costs[correcting])),
                    "median_other_ticks": float(np.median(costs[~correcting])) if every > 1 else None,
                    "load": load,
                    "ref": ref,
                }
            )
        report["cost_us"][name] = sorted(trials, key=lambda t: float(t["median"] or 0.0))
        best, worst = report["cost_us"][name][0], report["cost_us"][name][-1]
        print(
            f"cost {name:13s} best: median {best['median']:.1f} mean {best['mean']:.1f} p99 {best['p99']:.1f} "
            f"[correction ticks {best['median_correction_ticks']:.1f}, others {best['median_other_ticks'] or 0:.1f}] "
            f"(load {best['load']:.1f}, a+a {best['ref']:.2f} us) | worst: median {worst['median']:.1f} "
            f"mean {worst['mean']:.1f} p99 {worst['p99']:.1f}"
        )
    for k, v in report["lie_us"].items():
        print(f"exp: {k}: {v:.2f} us")
    if not args.skip_accuracy:
        for profile in PROFILES:
            runs = [record_g1_sway(robot, duration=6.0, profile=profile, seed=s) for s in range(3)]
            for name in FILTERS:
                syn = synthetic_accuracy(name, profile)
                g1 = g1_accuracy(robot, runs, name, profile)
                report["synthetic"][f"{profile}/{name}"] = syn
                report["g1"][f"{profile}/{name}"] = g1
                print(f"{profile:8s} {name:13s} synthetic " + " ".join(f"{k} {v:.4f}" for k, v in syn.items()))
                print(f"{'':8s} {'':13s} g1        " + " ".join(f"{k} {v:.4f}" for k, v in g1.items()))
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(report, fh, indent=1)
    return report


if __name__ == "__main__":
    main()
