"""Gyro-bias calibration at standstill: the sample mean recovers a known bias with the std it reports
(s / sqrt(N), checked over many calibrations), and it removes the heading drift that a yaw-rate bias
causes on ONE point contact, where the filter cannot observe that bias (without the calibration the
heading drifts as b_z t); bad samples raise InputError."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gaitshift.control.estimation import FilterTuning, FootKinematics, GyroCalibration, ImuReading, make_filter
from gaitshift.errors import InputError

DT = 0.002
G = 9.81
BIAS = np.array([0.004, -0.006, 0.0175])  # rad/s, about 1 deg/s on z (the BMI088's turn-on offset)
SIGMA = 0.005  # per-sample gyro noise, rad/s


def test_the_calibration_mean_has_the_std_it_reports():
    rng = np.random.default_rng(0)
    errors, stds = [], []
    for _ in range(400):
        cal = GyroCalibration.from_samples(BIAS + rng.normal(0.0, SIGMA, (500, 3)), DT)
        errors.append(cal.bias - BIAS)
        stds.append(cal.std)
    spread = float(np.std(np.array(errors)))
    assert np.mean(stds) == pytest.approx(SIGMA / np.sqrt(500), rel=0.05)
    assert spread == pytest.approx(np.mean(stds), rel=0.1)


def _yaw_after(calibration: GyroCalibration | None, seconds: float) -> float:
    """Heading error (rad) of the point InEKF on one still stance foot with a constant gyro bias."""
    imu = ImuReading(gyro=BIAS, accel=np.array([0.0, 0.0, G]))
    left = np.array([0.05, 0.1, -0.7])
    flat = np.stack([np.eye(3)] * 2)
    zero = np.zeros(2)
    feet = FootKinematics(pos=np.stack([left, left]), vel=np.zeros((2, 3)), var=zero, rot=flat, rot_var=zero)
    f = make_filter("inekf", FilterTuning(contact_density=1e-4, gyro_bias_std=0.02))
    f.reset(np.eye(3), np.array([0.0, 0.0, 0.7]), None, calibration)
    for _ in range(round(seconds / DT)):
        state = f.step(imu, feet, np.array([True, False]), DT)
    return float(Rotation.from_matrix(state.rot).as_rotvec()[2])


def test_a_calibrated_bias_stops_the_unobservable_heading_drift():
    drift = _yaw_after(None, 4.0)
    assert abs(drift) > 0.5 * BIAS[2] * 4.0  # one point contact: the yaw-rate bias is not learned
    cal = GyroCalibration(bias=BIAS.copy(), std=1e-4)
    assert abs(_yaw_after(cal, 4.0)) < 1e-3


@pytest.mark.parametrize(("samples", "dt"), [(np.zeros((1, 3)), DT), (np.zeros((10, 2)), DT), (np.zeros((10, 3)), 0.0)])
def test_bad_samples_raise_input_error(samples, dt):
    with pytest.raises(InputError):
        GyroCalibration.from_samples(samples, dt)
