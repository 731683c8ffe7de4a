"""Filter consistency: on synthetic walks whose noise follows the filter's own model exactly, the
average NEES (ANEES) of the InEKF's base error (rotation, velocity, position: 9 dof) over N runs lies
inside its chi-square band. The error is computed with scipy and closed forms (estimation_truth), each
run starts from an initial error drawn from the filter's prior, the truth is analytic.

Checks: the ANEES of each of 4 instants 0.5 s apart inside its two-sided 99 % band (4 correlated
checks: 99 % each keeps the family near 95 %), and their mean inside the 95 % band of one instant
(conservative: averaging over time only narrows the true spread). For scale, with N = 100 the
ANEES of one instant has a standard deviation of sqrt(2 * 9 / 100) = 0.42 around 9.

Checked: the point-contact filter correcting every tick (Hartley 2018 as published) and the default
set-up (flat feet, corrections every ``correct_every`` ticks); docs/estimation.md lists the ANEES
of every combination (the point filter at 4 ticks is ~3 % more optimistic at one instant).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from estimation_truth import perturb, right_invariant_error, se23
from scipy.stats import chi2

from gaitshift.bench.synthetic import synthetic_readings, synthetic_walk
from gaitshift.control.estimation import Channel, FilterTuning, NoiseProfile, make_filter

RUNS = 100
EVERY = 250  # ticks between NEES samples (0.5 s)

TUNING = FilterTuning(
    gyro_density=2e-3,
    accel_density=2e-2,
    gyro_bias_walk=1e-3,
    accel_bias_walk=1e-2,
    gyro_bias_std=0.01,
    accel_bias_std=0.1,
    contact_density=1e-4,  # the synthetic stance soles do not move
    contact_rot_density=1e-4,
    foot_floor=0.003,
    foot_rot_floor=0.01,
)
PROFILE = NoiseProfile(  # the same numbers as sensor noise: white, turn-on bias, random walk
    name="consistency",
    gyro=Channel(density=TUNING.gyro_density),
    accel=Channel(density=TUNING.accel_density),
    gyro_bias=TUNING.gyro_bias_std,
    accel_bias=TUNING.accel_bias_std,
    gyro_bias_walk=TUNING.gyro_bias_walk,
    accel_bias_walk=TUNING.accel_bias_walk,
)


def _average_nees(name: str, correct_every: int) -> np.ndarray:
    walk = synthetic_walk(2.0)
    checks = np.arange(EVERY, walk.t.size, EVERY)
    nees = np.zeros((RUNS, checks.size))
    prior = np.array(
        [TUNING.init_tilt_std] * 2 + [TUNING.init_yaw_std] + [TUNING.init_vel_std] * 3 + [TUNING.init_pos_std] * 3
    )
    for run in range(RUNS):
        rng = np.random.default_rng(1000 + run)
        imu, feet, _ = synthetic_readings(
            walk,
            PROFILE,
            foot_pos_std=TUNING.foot_floor,
            foot_vel_std=0.0,
            foot_rot_std=TUNING.foot_rot_floor,
            seed=run,
        )
        start = perturb(se23(walk.rot[0], walk.vel[0], walk.pos[0]), rng.normal(0.0, prior))
        f = make_filter(name, replace(TUNING, correct_every=correct_every))
        f.reset(start[0:3, 0:3], start[0:3, 4], start[0:3, 3])
        j = 0
        for k in range(1, walk.t.size):
            s = f.step(imu[k], feet[k], walk.contact[k], walk.dt)
            if j < checks.size and k == checks[j]:
                xi = right_invariant_error(se23(walk.rot[k], walk.vel[k], walk.pos[k]), se23(s.rot, s.vel, s.pos))
                nees[run, j] = xi @ np.linalg.solve(f.world_covariance()[0:9, 0:9], xi)
                j += 1
    return nees.mean(axis=0)


@pytest.mark.parametrize(
    ("name", "correct_every"),
    [("inekf", 1), ("inekf-flat", FilterTuning().correct_every)],  # Hartley's filter; the default set-up
)
def test_average_nees_of_the_base_lies_in_its_chi_square_band(name, correct_every):
    avg = _average_nees(name, correct_every)
    low, high = chi2.ppf([0.005, 0.995], 9 * RUNS) / RUNS
    assert np.all((avg > low) & (avg < high)), (low, high, np.round(avg, 2))
    low, high = chi2.ppf([0.025, 0.975], 9 * RUNS) / RUNS
    assert low < avg.mean() < high, (low, high, np.round(avg, 2))
