"""Joint filter: its stationary gain is the fixed point of the Kalman covariance recursion (iterated
here, independently of scipy's Riccati solver), and on walking-like joint motion (0.4 rad at 1, 2 and
3.5 Hz) its velocity beats the driver's: a little for the typical profile (an encoder difference
over one tick is already good; its error is mostly the half-tick lag), about halves it for the
rl-peer noise (+-1.5 rad/s uniform); with the commanded acceleration as the prediction's input a
constant acceleration leaves no lag (without it the velocity trails by a fixed amount), and the input
does not change what the filter does with the noise."""

from __future__ import annotations

import numpy as np
import pytest

from gaitshift.control.estimation import FilterTuning, JointVelocityFilter, SensorNoise
from gaitshift.errors import InputError

DT = 0.002


def test_gain_is_the_fixed_point_of_the_kalman_recursion():
    f = JointVelocityFilter(1, DT, pos_std=1e-3, vel_std=0.5, accel_density=40.0)
    a = np.array([[1.0, DT], [0.0, 1.0]])
    q = 40.0**2 * np.array([[DT**3 / 3, DT**2 / 2], [DT**2 / 2, DT]])
    r = np.diag([1e-3**2, 0.5**2])
    p = np.eye(2)
    for _ in range(20000):
        prior = a @ p @ a.T + q
        gain = prior @ np.linalg.inv(prior + r)
        p = (np.eye(2) - gain) @ prior
    np.testing.assert_allclose(f.gain, gain, rtol=1e-6)


@pytest.mark.parametrize(("profile", "ratio"), [("typical", 1.0), ("rl-peer", 0.6)])
def test_filtered_velocity_beats_the_raw_driver_velocity(profile, ratio):
    t = np.arange(2500) * DT
    amp, freq = 0.4, np.array([1.0, 2.0, 3.5])  # rad, Hz: walking joint motion
    q = amp * np.sin(2 * np.pi * freq[:, None] * t).T  # (K, 3)
    qd = amp * 2 * np.pi * freq * np.cos(2 * np.pi * freq[:, None] * t).T
    noise = SensorNoise(profile, DT, 3, weight=1.0, seed=1)
    tun = FilterTuning.from_profile(profile, DT)
    f = JointVelocityFilter(3, DT, tun.encoder_std, tun.joint_vel_std, tun.joint_accel_density)
    raw_q, raw_qd, est_q, est_qd = [], [], [], []
    for k in range(t.size):
        r = noise.joints(q[k], qd[k])
        fq, fqd = f.update(r.q, r.qd)
        raw_q.append(r.q), raw_qd.append(r.qd), est_q.append(fq), est_qd.append(fqd)
    settled = slice(250, None)

    def rms(x, ref):
        return float(np.sqrt(np.mean((np.array(x)[settled] - ref[settled]) ** 2)))

    assert rms(est_qd, qd) < ratio * rms(raw_qd, qd)
    assert rms(est_q, q) <= rms(raw_q, q) * 1.05  # positions: no worse than the encoder


def test_the_commanded_acceleration_removes_the_lag_and_keeps_the_noise_gain():
    f, g = (JointVelocityFilter(1, DT, pos_std=0.0058, vel_std=0.87, accel_density=10.0) for _ in range(2))
    f.reset(np.zeros(1))
    g.reset(np.zeros(1))
    a = 100.0  # rad/s^2, held
    for k in range(1, 500):
        t = k * DT
        q, qd = np.array([0.5 * a * t * t]), np.array([a * t])
        _, with_input = f.update(q, qd, np.array([a]))
        _, without = g.update(q, qd)
    assert abs(with_input[0] - a * t) < 1e-9
    assert a * t - without[0] > 0.1  # trails (0.27 rad/s at these settings)
    rng = np.random.default_rng(0)
    h, n = (JointVelocityFilter(200, DT, pos_std=0.0058, vel_std=0.87, accel_density=10.0) for _ in range(2))
    h.reset(np.zeros(200))
    n.reset(np.zeros(200))
    for _ in range(300):  # noise only, zero command: the same estimate
        zq, zv = rng.normal(0, 0.0058, 200), rng.normal(0, 0.87, 200)
        np.testing.assert_array_equal(h.update(zq, zv, np.zeros(200))[1], n.update(zq, zv)[1])


def test_bad_settings_raise_input_error():
    with pytest.raises(InputError):
        JointVelocityFilter(3, DT, pos_std=0.0, vel_std=0.1, accel_density=10.0)
