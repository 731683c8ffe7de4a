"""What the filters assume about the sensors and the contact: one frozen set of numbers per run.

:meth:`FilterTuning.from_profile` derives the sensor part from a :class:`NoiseProfile` at the tick
period (eq. (1) of :mod:`gaitshift.control.estimation.noise`: a per-sample variance ``s^2`` is the
continuous density ``sqrt(s^2 dt)``); the contact and model parts are robot facts, not sensor facts,
and keep their defaults unless given.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from gaitshift.control.estimation.noise import NoiseProfile, noise_profile
from gaitshift.errors import InputError


@dataclass(frozen=True)
class FilterTuning:
    """Noise model and gains of the base filters and the joint filter (SI units).

    Attributes:
        gyro_density: gyro white noise, rad/s/sqrt(Hz).
        accel_density: accelerometer white noise, m/s^2/sqrt(Hz).
        gyro_bias_walk, accel_bias_walk: bias random walks, rad/s/sqrt(s), m/s^2/sqrt(s).
        gyro_bias_std, accel_bias_std: prior std of the biases at reset.
        encoder_std: std of one joint-position reading, rad (mapped to the soles by ``J``).
        joint_vel_std: std of one driver velocity reading, rad/s.
        joint_accel_density: white joint acceleration of the joint filter's model, rad/s^2/sqrt(Hz).
        contact_density: velocity random walk of a stance foot (rolling, small slip), m/s/sqrt(Hz).
        foot_floor: std of the sole position beyond encoder noise (sole rolling, link flex), m.
        floor_std: std of a flat stance sole's height above a known floor (contact compliance), m
            (:mod:`gaitshift.control.estimation.floor`).
        contact_rot_density: orientation random walk of a stance sole (flat feet), rad/sqrt(s).
        foot_rot_floor: std of the sole orientation beyond encoder noise (flat feet), rad.
        init_tilt_std, init_yaw_std: prior std of roll/pitch and yaw at reset, rad.
        init_vel_std, init_pos_std: prior std of velocity (m/s) and position (m) at reset.
        attitude_tau: leg odometry: time constant of the accelerometer tilt correction, s.
        bias_tau: leg odometry: time constant of its gyro-bias integrator, s.
        velocity_tau: leg odometry: time constant of the kinematic-velocity blend, s.
        correct_every: InEKF: ticks between covariance propagations and foot corrections (the mean
            follows the IMU every tick); 1 = every tick.
    """

    gyro_density: float = 2.5e-4
    accel_density: float = 1.7e-3
    gyro_bias_walk: float = 1e-4
    accel_bias_walk: float = 1e-3
    gyro_bias_std: float = 0.02
    accel_bias_std: float = 0.2
    encoder_std: float = 1e-4
    joint_vel_std: float = 0.1
    joint_accel_density: float = 10.0
    contact_density: float = 0.01
    foot_floor: float = 0.002
    floor_std: float = 0.002
    contact_rot_density: float = 0.01
    foot_rot_floor: float = 0.01
    init_tilt_std: float = 0.02
    init_yaw_std: float = 0.02
    init_vel_std: float = 0.1
    init_pos_std: float = 0.01
    attitude_tau: float = 1.0
    bias_tau: float = 10.0
    velocity_tau: float = 0.02
    correct_every: int = 4

    def __post_init__(self) -> None:
        for name, value in vars(self).items():
            if not (math.isfinite(value) and value >= 0.0):
                raise InputError(f"tuning.{name}", value, "a finite number >= 0")
        if int(self.correct_every) != self.correct_every or self.correct_every < 1:
            raise InputError("tuning.correct_every", self.correct_every, "an integer >= 1 (ticks)")
        for name in ("attitude_tau", "bias_tau", "velocity_tau", "foot_floor", "floor_std", "foot_rot_floor"):
            if getattr(self, name) <= 0.0:
                raise InputError(f"tuning.{name}", getattr(self, name), "a number > 0")

    @classmethod
    def from_profile(cls, profile: str | NoiseProfile, dt: float, **overrides: Any) -> FilterTuning:
        """The tuning that matches a noise profile at tick period ``dt`` s (sensor fields only).

        Bias priors never go below 1e-3 rad/s and 1e-2 m/s^2 (a filter must be able to learn an
        unmodelled offset); other fields keep their defaults unless given in ``overrides``.
        """
        p = noise_profile(profile)
        if not dt > 0:
            raise InputError("dt", dt, "a period > 0 s")
        fields: dict[str, Any] = {
            "gyro_density": math.sqrt(p.gyro.variance(dt) * dt) or 1e-5,
            "accel_density": math.sqrt(p.accel.variance(dt) * dt) or 1e-4,
            "gyro_bias_walk": max(p.gyro_bias_walk, 1e-6),
            "accel_bias_walk": max(p.accel_bias_walk, 1e-5),
            "gyro_bias_std": max(p.gyro_bias, 1e-3),
            "accel_bias_std": max(p.accel_bias, 1e-2),
            "encoder_std": max(p.joint_pos_std(dt), 1e-6),
            "joint_vel_std": max(p.joint_vel_std(dt), 1e-4),
        }
        fields.update(overrides)
        return cls(**fields)
