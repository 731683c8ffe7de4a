"""Analytic cases of the base filters: a still IMU keeps its state and the InEKF learns a constant gyro
bias from the stance feet; a base at constant velocity over stance feet converges to that velocity; a
constant gyro rate for 1 s gives exp(w t) (scipy's rotation, not the filter's group code).

With ONE point contact and a still, level IMU, a yaw-rate bias b and a horizontal velocity error
``b e_z x (d - p)`` move the predicted sole identically to first order in time, so neither is
observable alone (the filter is right to keep them uncertain); two point contacts (different lever
arms) separate them, which is why the bias and velocity cases stand on both feet."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gaitshift.control.estimation import FILTERS, FilterTuning, FootKinematics, ImuReading, InvariantEKF, make_filter

G = 9.81
DT = 0.002
#: a rigid contact (the analytic feet do not move): the filters' math, not a tuning for a real sole
RIGID = FilterTuning(contact_density=1e-4)
FOOT = np.array([0.05, 0.1, -0.7])  # stance sole in the IMU frame, m (horizontal lever arm: yaw observable)


RIGHT = np.array([0.0, -0.1, -0.7])


def _feet(left: np.ndarray, right: np.ndarray = RIGHT, vel: np.ndarray | None = None) -> FootKinematics:
    v = np.zeros((2, 3)) if vel is None else np.stack([vel, vel])
    flat = np.stack([np.eye(3), np.eye(3)])  # constant sole orientation: the analytic soles do not turn
    return FootKinematics(pos=np.stack([left, right]), vel=v, var=np.zeros(2), rot=flat, rot_var=np.zeros(2))


LEFT_DOWN = np.array([True, False])
BOTH_DOWN = np.array([True, True])


@pytest.mark.parametrize("name", sorted(FILTERS))
def test_still_imu_keeps_orientation_and_zero_velocity(name):
    rot0 = Rotation.from_rotvec([0.1, -0.05, 0.3]).as_matrix()
    imu = ImuReading(gyro=np.zeros(3), accel=rot0.T @ np.array([0.0, 0.0, G]))  # gravity reaction
    f = make_filter(name, RIGID)
    f.reset(rot0, np.array([0.0, 0.0, 0.7]))
    for _ in range(2500):
        state = f.step(imu, _feet(FOOT), LEFT_DOWN, DT)
    assert np.linalg.norm(Rotation.from_matrix(state.rot @ rot0.T).as_rotvec()) < 1e-9
    assert np.linalg.norm(state.vel) < 1e-9
    assert np.linalg.norm(state.pos - [0.0, 0.0, 0.7]) < 1e-9


@pytest.mark.parametrize(("name", "contact"), [("inekf", BOTH_DOWN), ("inekf-flat", LEFT_DOWN)])
def test_inekf_learns_a_constant_gyro_bias_from_the_stance_feet(name, contact):
    """Point contacts need two feet for the yaw-rate bias; a flat sole's orientation gives it on one."""
    bias = np.array([0.01, -0.02, 0.015])  # rad/s, the BMI088's zero-rate offset class
    imu = ImuReading(gyro=bias.copy(), accel=np.array([0.0, 0.0, G]))
    f = make_filter(name, RIGID)
    f.reset(np.eye(3), np.zeros(3))
    for _ in range(10000):  # 20 s
        state = f.step(imu, _feet(FOOT), contact, DT)
    assert np.abs(state.gyro_bias - bias).max() < 5e-4
    assert np.linalg.norm(state.omega) < 5e-4  # bias-corrected rate: the body is still
    tilt = Rotation.from_matrix(state.rot).as_rotvec()
    assert np.abs(tilt[0:2]).max() < 2e-3  # roll/pitch stay level (gravity observed)


def test_point_contact_inekf_cannot_learn_the_yaw_rate_bias_on_one_foot():
    """The unobservable case of the module docstring: the yaw-bias variance stays at its prior."""
    imu = ImuReading(gyro=np.array([0.0, 0.0, 0.015]), accel=np.array([0.0, 0.0, G]))
    f = InvariantEKF(RIGID)
    f.reset(np.eye(3), np.zeros(3))
    for _ in range(5000):
        f.step(imu, _feet(FOOT), LEFT_DOWN, DT)
    yaw_bias_std = np.sqrt(f.cov[f.nx - 4, f.nx - 4])
    assert yaw_bias_std > 0.9 * RIGID.gyro_bias_std


@pytest.mark.parametrize("name", sorted(FILTERS))
def test_constant_velocity_over_stance_feet_converges(name):
    v = np.array([0.4, -0.15, 0.05])  # m/s, world = IMU axes (level, no rotation)
    imu = ImuReading(gyro=np.zeros(3), accel=np.array([0.0, 0.0, G]))
    f = make_filter(name, RIGID)
    f.reset(np.eye(3), np.zeros(3), vel=np.zeros(3))  # starts wrong: at rest
    for k in range(1, 1001):  # 2 s; the feet recede as the base moves
        state = f.step(imu, _feet(FOOT - v * k * DT, RIGHT - v * k * DT, -v), BOTH_DOWN, DT)
    assert np.linalg.norm(state.vel - v) < 1e-3


@pytest.mark.parametrize("name", sorted(FILTERS))
def test_constant_rate_for_one_second_is_the_exponential(name):
    w = np.array([0.3, -0.2, 0.5])  # rad/s, body frame
    f = make_filter(name, RIGID)
    f.reset(np.eye(3), np.zeros(3))
    no_contact = np.array([False, False])
    for k in range(1, 501):  # gravity reaction in the IMU frame at the start of each interval
        rot_start = Rotation.from_rotvec(w * (k - 1) * DT).as_matrix()
        state = f.step(ImuReading(w, rot_start.T @ [0.0, 0.0, G]), _feet(FOOT), no_contact, DT)
    expected = Rotation.from_rotvec(w * 1.0).as_matrix()
    assert np.linalg.norm(Rotation.from_matrix(state.rot @ expected.T).as_rotvec()) < 1e-9
    assert np.linalg.norm(state.vel) < 1e-6  # the gravity reaction cancels g


def _pitch(theta: float) -> np.ndarray:
    return Rotation.from_rotvec([0.0, theta, 0.0]).as_matrix()


def _rolling_feet(t: float, point: np.ndarray, r: np.ndarray, rate: float) -> FootKinematics:
    """The left sole rolling in pitch at ``rate`` rad/s about its sole-frame point ``r``, which stays at
    ``point`` (IMU frame): the centre at ``point - R_f r``; the right sole still and flat."""
    rot_f = _pitch(rate * t)
    centre = point - rot_f @ r
    rots = np.stack([rot_f, np.eye(3)])
    vel = np.stack([-np.cross([0.0, rate, 0.0], rot_f @ r), np.zeros(3)])
    return FootKinematics(pos=np.stack([centre, RIGHT]), vel=vel, var=np.zeros(2), rot=rots, rot_var=np.zeros(2))


@pytest.mark.parametrize(("placed", "still"), [(True, True), (False, False)])
def test_a_sole_rolling_about_its_centre_of_pressure_leaves_a_still_base_still(placed, still):
    """A still base on a sole that rolls 0.15 rad about its toe (the CoP 8 cm ahead of the centre): with
    the stance point at the CoP the base reads still; at the sole's centre it reads the centre's motion
    (about 2.4 cm/s, the "under-read" of a rolling running sole)."""
    toe, point, rate = np.array([0.08, 0.0, 0.0]), FOOT + np.array([0.08, 0.0, 0.0]), 0.3
    imu = ImuReading(gyro=np.zeros(3), accel=np.array([0.0, 0.0, G]))
    f = InvariantEKF(RIGID)
    f.reset(np.eye(3), np.zeros(3))
    for k in range(251):  # 0.5 s
        if placed:
            f.place_contacts(np.array([toe[0:2], [np.nan, np.nan]]))
        state = f.step(imu, _rolling_feet(k * DT, point, toe, rate), LEFT_DOWN, DT)
    assert (np.linalg.norm(state.vel) < 1e-3 and np.linalg.norm(state.pos) < 1e-3) == still, state.vel


def test_a_centre_of_pressure_moving_on_a_still_sole_moves_nothing():
    """Both soles still and flat; the left one's CoP sweeps from heel to toe (16 cm in 0.5 s) and the right
    one's stays off centre: the stored points move with the CoP, so the base stays where it is, at rest."""
    imu = ImuReading(gyro=np.zeros(3), accel=np.array([0.0, 0.0, G]))
    f = InvariantEKF(RIGID)
    f.reset(np.eye(3), np.zeros(3))
    for k in range(251):
        cop = np.array([[-0.08 + 0.16 * k / 250, 0.01], [0.02, -0.02]])
        f.place_contacts(cop)
        state = f.step(imu, _feet(FOOT), BOTH_DOWN, DT)
    assert np.linalg.norm(state.vel) < 1e-6
    assert np.linalg.norm(state.pos) < 1e-6
