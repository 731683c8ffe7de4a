"""Noise profiles: the corrupter's samples have the variance of eq. (1) (Gaussian density and uniform
half-width), encoders are quantised to their resolution, biases walk at their rate, the rl-peer
bounds hold, and the filter tuning derived from a profile has the equivalent continuous density."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gaitshift.control.estimation import PROFILES, Channel, FilterTuning, noise_profile
from gaitshift.errors import InputError
from gaitshift.sim.sensor_noise import SensorNoise

DT = 0.002


def test_channel_variance_is_density_squared_over_dt_plus_uniform_squared_over_three():
    ch = Channel(density=0.01, uniform=0.2)
    draws = ch.sample(np.random.default_rng(0), DT, (200000,))
    expected = 0.01**2 / DT + 0.2**2 / 3
    assert abs(draws.var() / expected - 1.0) < 0.02
    assert ch.variance(DT) == pytest.approx(expected)


def test_typical_encoder_is_quantised_to_14_bits():
    noise = SensorNoise("typical", DT, 5, weight=1.0, seed=0)
    q = np.random.default_rng(1).uniform(-1, 1, 5)
    reading = noise.joints(q, np.zeros(5))
    lsb = 2 * math.pi / 2**14
    np.testing.assert_allclose(reading.q / lsb, np.round(reading.q / lsb), atol=1e-9)
    assert np.abs(reading.q - q).max() <= lsb / 2 + 1e-12


def test_rl_peer_noise_stays_inside_its_uniform_bounds():
    noise = SensorNoise("rl-peer", DT, 29, weight=1.0, seed=2)
    gyro, joint_q, joint_qd = [], [], []
    for _ in range(2000):
        r = noise.imu(np.zeros(3), np.zeros(3))
        j = noise.joints(np.zeros(29), np.zeros(29))
        gyro.append(r.gyro), joint_q.append(j.q), joint_qd.append(j.qd)
    assert np.abs(gyro).max() <= 0.2 and np.abs(gyro).max() > 0.19
    assert np.abs(joint_q).max() <= 0.01 and np.abs(joint_qd).max() <= 1.5
    assert np.abs(joint_qd).max() > 1.45  # uniform: the edges are reached


def test_gyro_bias_random_walk_grows_with_the_square_root_of_time():
    walks = []
    for seed in range(200):
        noise = SensorNoise("typical", DT, 0, weight=1.0, seed=seed)
        start = noise.gyro_bias.copy()
        for _ in range(500):
            noise.imu(np.zeros(3), np.zeros(3))
        walks.append(noise.gyro_bias - start)
    expected = PROFILES["typical"].gyro_bias_walk * math.sqrt(500 * DT)
    assert abs(np.std(walks) / expected - 1.0) < 0.1


def test_tuning_from_profile_is_the_equivalent_density():
    tun = FilterTuning.from_profile("rl-peer", DT)
    assert tun.gyro_density == pytest.approx(math.sqrt(0.2**2 / 3 * DT))
    assert tun.encoder_std == pytest.approx(0.01 / math.sqrt(3))


def test_unknown_profile_raises_input_error():
    with pytest.raises(InputError) as err:
        noise_profile("perfect")
    assert err.value.field == "noise"
