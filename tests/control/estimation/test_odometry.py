"""Leg odometry (the baseline) and the InEKF against the analytic truth of the same noisy synthetic walk
(typical BMI088-class IMU, 2 mm / 2 cm/s sole noise): both track the velocity; the InEKF, which
estimates the biases, keeps the tilt and the height better (the baseline re-anchors each foot with a
tilted estimate, so its height drifts step by step). Errors are computed with scipy."""

from __future__ import annotations

import numpy as np
import pytest
from estimation_truth import run
from scipy.spatial.transform import Rotation

from gaitshift.bench.synthetic import synthetic_readings, synthetic_walk
from gaitshift.control.estimation import FilterTuning, make_filter


@pytest.fixture(scope="module")
def errors():
    walk = synthetic_walk(8.0)
    imu, feet, _ = synthetic_readings(walk, "typical", seed=3)
    out = {}
    for name in ("leg-odometry", "inekf"):
        f = make_filter(name, FilterTuning.from_profile("typical", walk.dt))
        f.reset(walk.rot[0], walk.pos[0], walk.vel[0])
        states = run(f, walk, imu, feet)
        rot_err = np.array([Rotation.from_matrix(walk.rot[k + 1] @ s.rot.T).as_rotvec() for k, s in enumerate(states)])
        vel_err = np.array([s.vel for s in states]) - walk.vel[1:]
        pos_err = np.array([s.pos for s in states]) - walk.pos[1:]
        settled = slice(walk.t.size // 4, None)  # after 2 s (bias and tilt transients)
        out[name] = {
            "tilt": float(np.sqrt(np.mean(np.sum(rot_err[settled, 0:2] ** 2, axis=1)))),
            "vel": float(np.sqrt(np.mean(np.sum(vel_err[settled] ** 2, axis=1)))),
            "height": float(abs(pos_err[-1, 2])),
        }
    return out


def test_leg_odometry_tracks_the_walk(errors):
    e = errors["leg-odometry"]
    # velocity within 12 % of the 0.5 m/s walk. Tilt: the accelerometer correction (tau = 1 s) sees the
    # walk's +-5 m/s^2 surge at 2.5 Hz, attenuated by 1 / (2 pi 2.5 Hz 1 s): ~0.03 rad; allow twice that
    assert e["vel"] < 0.06
    assert e["tilt"] < 0.06


def test_inekf_beats_the_baseline_on_tilt_and_height(errors):
    ekf, odo = errors["inekf"], errors["leg-odometry"]
    assert ekf["vel"] < 0.03
    assert ekf["tilt"] < 0.5 * odo["tilt"]
    assert ekf["height"] < 0.01 < odo["height"]
