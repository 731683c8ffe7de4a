"""The facade on a simulated G1 (MuJoCo physics, its own sensors with the typical noise, truth from the
simulator): base tilt, velocity, CoM and CoM velocity are tracked, contacts match the true sole loads,
a sole pushed across a slippery floor is flagged as slipping (and only that one), the MuJoCo-style
qpos/qvel are consistent, and bad settings raise InputError.

Tilt bound: while the robot barely rotates, a horizontal accelerometer bias ``b_xy`` cannot be told
from a tilt of ``|b_xy| / g`` (the BMI088's zero-g offset, 20 mg, is 0.02 rad), so the bound is that
ambiguity (the true bias, replayed from the run's seed) plus the filter's own error."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gaitshift.bench.g1sway import record_g1_sway
from gaitshift.control.estimation import FILTERS, StateEstimator
from gaitshift.errors import InputError
from gaitshift.robots import load_robot
from gaitshift.sim.sensor_noise import SensorNoise


@pytest.fixture(scope="module")
def g1():
    return load_robot("g1")


SEED = 2


@pytest.fixture(scope="module")
def sway(g1):
    return record_g1_sway(g1, duration=4.0, profile="typical", seed=SEED)


def _bias_tilt(g1, run):
    """|b_xy| / g of the run's true accelerometer bias (the same seeded draw as the recording)."""
    model = g1.model()
    bias = SensorNoise("typical", run.dt, model.nu, 1.0, SEED).accel_bias
    return float(np.linalg.norm(bias[0:2]) / 9.81)


def _estimate(g1, run, **kwargs):
    est = StateEstimator.from_robot(g1, run.dt, noise="typical", **kwargs)
    est.reset(run.qpos0, run.qvel0)
    return [est.step(run.imu[k], run.joints[k], run.forces[k]) for k in range(len(run.imu))]


def _rms(err):
    return float(np.sqrt(np.mean(np.sum(np.square(err), axis=-1))))


@pytest.mark.parametrize("name", sorted(FILTERS))
def test_tracks_the_simulated_g1(g1, sway, name):
    states = _estimate(g1, sway, filter=name)
    quat = np.array([s.base_quat for s in states])
    rot_err = (
        Rotation.from_quat(sway.qpos[:, 3:7], scalar_first=True) * Rotation.from_quat(quat, scalar_first=True).inv()
    ).as_rotvec()
    tilt = _rms(rot_err[:, 0:2])
    # own error: InEKF a few mrad; the baseline's complementary attitude (tau = 1 s) feels the sway
    own = 0.04 if name == "leg-odometry" else 0.005
    ambiguity = _bias_tilt(g1, sway)
    assert tilt < ambiguity + own
    assert _rms(np.array([s.base_vel for s in states]) - sway.qvel[:, 0:3]) < 0.03
    assert _rms(np.array([s.com_vel for s in states]) - sway.com_vel) < 0.03
    assert _rms(np.array([s.com for s in states]) - sway.com) < 0.7 * (ambiguity + own)  # tilt x CoM height
    assert np.mean(np.array([s.contact for s in states]) == sway.contact) > 0.98
    assert not np.any([s.slip for s in states])


def test_flags_the_sole_that_slides(g1):
    run = record_g1_sway(g1, duration=3.0, profile="typical", seed=2, slippery=0, push=(2.0, 2.4, 40.0))
    slip = np.array([s.slip for s in _estimate(g1, run)])
    speed = np.linalg.norm(run.foot_vel[:, :, 0:2], axis=2)
    sliding = run.contact[:, 0] & (speed[:, 0] > 0.2)  # the default slip speed
    assert sliding.sum() > 100  # the scenario does slide (0.2 s and more)
    assert slip[sliding, 0].mean() > 0.5
    assert not slip[:, 1].any()
    still = run.contact[:, 0] & (speed[:, 0] < 0.05)
    assert slip[still, 0].mean() < 0.05  # a still sole is (almost) never flagged


def test_qpos_and_qvel_are_mujoco_conventions(g1, sway):
    state = _estimate(g1, sway)[-1]
    qpos, qvel = state.qpos(), state.qvel()
    nj = g1.model().nv - 6
    assert qpos.shape == (7 + nj,) and qvel.shape == (6 + nj,)
    assert np.linalg.norm(qpos[3:7]) == pytest.approx(1.0)
    rot = Rotation.from_quat(state.base_quat, scalar_first=True).as_matrix()
    np.testing.assert_allclose(qvel[3:6], rot.T @ state.base_omega, atol=1e-12)  # body-frame angular velocity
    np.testing.assert_array_equal(qvel[6:], state.qd)


def test_bad_settings_raise_input_error(g1):
    with pytest.raises(InputError) as err:
        StateEstimator.from_robot(g1, 0.002, filter="kalman")
    assert err.value.field == "estimator.filter"
    with pytest.raises(InputError):
        StateEstimator.from_robot(g1, 0.002, imu_site="no_such_site")
    est = StateEstimator.from_robot(g1, 0.002)
    with pytest.raises(InputError):
        est.reset(np.zeros(5))
