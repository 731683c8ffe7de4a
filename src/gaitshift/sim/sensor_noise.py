"""The seeded corrupter that turns a world's true signals into what a robot reads, per a
:class:`~gaitshift.control.estimation.noise.NoiseProfile` (eq. (1) of that module: white noise per
sample, a turn-on bias plus a random walk, encoder quantisation, driver velocities from encoder
differences). The world's side of the truth barrier: the controller only knows the profile's numbers.
"""

from __future__ import annotations

import math

import numpy as np

from gaitshift.control.estimation.noise import NoiseProfile, noise_profile
from gaitshift.control.estimation.types import FootForces, ImuReading, JointReading

__all__ = ["SensorNoise"]


class SensorNoise:
    """Corrupts true signals into readings, per a :class:`NoiseProfile` (seeded, one instance per run).

    Args:
        profile: the noise profile (or its name).
        dt: sample period, s.
        n_joints: number of joints.
        weight: robot weight, N (scales the force noise).
        seed: random seed.
    """

    def __init__(self, profile: str | NoiseProfile, dt: float, n_joints: int, weight: float, seed: int = 0):
        self.profile = noise_profile(profile)
        self.dt = float(dt)
        self.weight = float(weight)
        self.rng = np.random.default_rng(seed)
        p = self.profile
        #: current true biases (turn-on offset plus random walk), rad/s and m/s^2
        self.gyro_bias = self.rng.normal(0.0, p.gyro_bias, 3) if p.gyro_bias > 0 else np.zeros(3)
        self.accel_bias = self.rng.normal(0.0, p.accel_bias, 3) if p.accel_bias > 0 else np.zeros(3)
        self._q_prev: np.ndarray | None = None
        self.n_joints = n_joints

    def imu(self, gyro: np.ndarray, accel: np.ndarray) -> ImuReading:
        """The IMU reading of the true angular velocity (3,) and specific force (3,), IMU frame."""
        p, dt, rng = self.profile, self.dt, self.rng
        if p.gyro_bias_walk > 0:
            self.gyro_bias = self.gyro_bias + rng.normal(0.0, p.gyro_bias_walk * math.sqrt(dt), 3)
        if p.accel_bias_walk > 0:
            self.accel_bias = self.accel_bias + rng.normal(0.0, p.accel_bias_walk * math.sqrt(dt), 3)
        return ImuReading(
            gyro=np.asarray(gyro, dtype=float) + self.gyro_bias + p.gyro.sample(rng, dt, (3,)),
            accel=np.asarray(accel, dtype=float) + self.accel_bias + p.accel.sample(rng, dt, (3,)),
        )

    def joints(self, q: np.ndarray, qd: np.ndarray) -> JointReading:
        """Encoder and driver readings of the true joint positions and velocities (nj,)."""
        p, dt, rng = self.profile, self.dt, self.rng
        q_read = np.asarray(q, dtype=float) + p.joint_pos.sample(rng, dt, (self.n_joints,))
        lsb = p.encoder_lsb
        if lsb > 0:
            q_read = np.round(q_read / lsb) * lsb
        if p.velocity_from_encoder:
            prev = self._q_prev if self._q_prev is not None else q_read - np.asarray(qd) * dt
            qd_read = (q_read - prev) / dt
        else:
            qd_read = np.asarray(qd, dtype=float).copy()
        self._q_prev = q_read
        qd_read = qd_read + p.joint_vel.sample(rng, dt, (self.n_joints,))
        return JointReading(q=q_read, qd=qd_read)

    def forces(self, normal: np.ndarray) -> FootForces:
        """The per-sole normal-force signal (2,) N of the true normal forces."""
        noise = self.rng.normal(0.0, self.profile.force * self.weight, 2) if self.profile.force > 0 else 0.0
        return FootForces(normal=np.asarray(normal, dtype=float) + noise)
