"""Sensor noise profiles: what the estimator is tuned to (the simulated world corrupts its sensors with
the same profiles, :class:`gaitshift.sim.sensor_noise.SensorNoise`).

A :class:`NoiseProfile` describes every sensor the estimator uses; :data:`PROFILES` holds the named
ones (the registry, see ``docs/estimation.md`` for the sources):

* ``ideal``: no noise, no bias, no quantisation (analytic tests);
* ``typical``: a MEMS IMU of the Bosch BMI088 class (datasheet BST-BMI088-DS001: gyro rate noise
  density 0.014 deg/s/sqrt(Hz), zero-rate offset 1 deg/s; accel noise density 175 ug/sqrt(Hz),
  zero-g offset 20 mg), 14-bit absolute joint encoders, driver velocity = encoder difference per tick,
  foot force noise 2 % of the weight;
* ``rl-peer``: the observation noise of the mjlab / Isaac Lab G1 velocity tasks, uniform per sample:
  gyro +-0.2 rad/s, projected gravity +-0.05 (applied as +-0.05 g on the accelerometer), joint
  position +-0.01 rad, joint velocity +-1.5 rad/s; no bias, no quantisation.

White noise of a channel (:class:`Channel`) per sample of period ``dt``::

    n_k = N(0, density^2 / dt) + U(-uniform, +uniform),   Var n_k = density^2 / dt + uniform^2 / 3   (1)

so a filter sees the equivalent continuous density ``sqrt(Var n_k * dt)``. Biases are a constant
turn-on offset ``N(0, bias^2)`` plus a random walk ``b_{k+1} = b_k + N(0, walk^2 dt)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from gaitshift.errors import InputError, check_choice

GRAVITY = 9.81


@dataclass(frozen=True)
class Channel:
    """White noise of one channel: Gaussian ``density`` (unit/sqrt(Hz)) plus uniform ``uniform``
    (half-width per sample, unit), see eq. (1)."""

    density: float = 0.0
    uniform: float = 0.0

    def variance(self, dt: float) -> float:
        """Per-sample variance at period ``dt`` s, eq. (1)."""
        return self.density**2 / dt + self.uniform**2 / 3.0

    def sample(self, rng: np.random.Generator, dt: float, shape: tuple[int, ...]) -> np.ndarray:
        """One draw of eq. (1) with the given shape."""
        out = np.zeros(shape)
        if self.density > 0.0:
            out += rng.normal(0.0, self.density / math.sqrt(dt), shape)
        if self.uniform > 0.0:
            out += rng.uniform(-self.uniform, self.uniform, shape)
        return out


@dataclass(frozen=True)
class NoiseProfile:
    """Noise of every sensor the estimator reads (SI units).

    Attributes:
        name: registry key.
        gyro: rad/s white noise; accel: m/s^2 white noise.
        gyro_bias, accel_bias: std of the constant turn-on bias, rad/s and m/s^2.
        gyro_bias_walk, accel_bias_walk: bias random walk, rad/s/sqrt(s) and m/s^2/sqrt(s).
        joint_pos: rad white noise on the encoder reading; encoder_bits: resolution (0 = exact).
        joint_vel: rad/s white noise on the driver velocity.
        velocity_from_encoder: the driver reports the difference of two quantised encoder readings
            over one tick (plus ``joint_vel``) instead of the true velocity plus ``joint_vel``.
        force: std of the per-sole normal force noise as a fraction of the robot weight.
        lsb_scale: factor on the encoder step (:meth:`scaled`).
    """

    name: str
    gyro: Channel = field(default_factory=Channel)
    accel: Channel = field(default_factory=Channel)
    gyro_bias: float = 0.0
    accel_bias: float = 0.0
    gyro_bias_walk: float = 0.0
    accel_bias_walk: float = 0.0
    joint_pos: Channel = field(default_factory=Channel)
    encoder_bits: int = 0
    joint_vel: Channel = field(default_factory=Channel)
    velocity_from_encoder: bool = False
    force: float = 0.0
    lsb_scale: float = 1.0

    @property
    def encoder_lsb(self) -> float:
        """Encoder resolution, rad (0 if exact), times ``lsb_scale``."""
        return self.lsb_scale * 2.0 * math.pi / 2**self.encoder_bits if self.encoder_bits > 0 else 0.0

    def scaled(self, k: float) -> NoiseProfile:
        """The same sensors with every noise magnitude times ``k`` >= 0: white-noise densities and
        ranges, bias offsets and random walks, the encoder step (``lsb_scale``) and the force noise.

        Raises:
            InputError: ``k`` negative or not finite.
        """
        if not (math.isfinite(k) and k >= 0):
            raise InputError("noise_scale", k, "a finite number >= 0")
        if k == 1.0:
            return self

        def ch(c: Channel) -> Channel:
            return Channel(density=k * c.density, uniform=k * c.uniform)

        return replace(
            self,
            name=f"{self.name} x{k:g}",
            gyro=ch(self.gyro),
            accel=ch(self.accel),
            gyro_bias=k * self.gyro_bias,
            accel_bias=k * self.accel_bias,
            gyro_bias_walk=k * self.gyro_bias_walk,
            accel_bias_walk=k * self.accel_bias_walk,
            joint_pos=ch(self.joint_pos),
            joint_vel=ch(self.joint_vel),
            force=k * self.force,
            lsb_scale=k * self.lsb_scale if k > 0 else 1.0,
            encoder_bits=self.encoder_bits if k > 0 else 0,
        )

    def joint_pos_std(self, dt: float) -> float:
        """Std of one joint-position reading: white noise and quantisation ``lsb / sqrt(12)``, rad."""
        return math.sqrt(self.joint_pos.variance(dt) + self.encoder_lsb**2 / 12.0)

    def joint_vel_std(self, dt: float) -> float:
        """Std of one driver velocity reading, rad/s (an encoder difference adds ``lsb / (dt sqrt 6)``)."""
        var = self.joint_vel.variance(dt)
        if self.velocity_from_encoder:
            var += 2.0 * self.joint_pos_std(dt) ** 2 / dt**2
        return math.sqrt(var)


DEG = math.pi / 180.0
MICRO_G = 1e-6 * GRAVITY

#: Named noise profiles (the registry; sources in docs/estimation.md).
PROFILES: dict[str, NoiseProfile] = {
    "ideal": NoiseProfile(name="ideal"),
    "none": NoiseProfile(name="none"),  # the simulator's name of "ideal"
    "typical": NoiseProfile(
        name="typical",
        gyro=Channel(density=0.014 * DEG),
        accel=Channel(density=175.0 * MICRO_G),
        gyro_bias=1.0 * DEG,
        accel_bias=20e-3 * GRAVITY,
        gyro_bias_walk=1e-4,
        accel_bias_walk=1e-3,
        encoder_bits=14,
        velocity_from_encoder=True,
        force=0.02,
    ),
    "rl-peer": NoiseProfile(
        name="rl-peer",
        gyro=Channel(uniform=0.2),
        accel=Channel(uniform=0.05 * GRAVITY),
        joint_pos=Channel(uniform=0.01),
        joint_vel=Channel(uniform=1.5),
        force=0.02,
    ),
}


def noise_profile(name: str | NoiseProfile) -> NoiseProfile:
    """The profile of that name (or the profile itself).

    Raises:
        InputError: unknown name.
    """
    if isinstance(name, NoiseProfile):
        return name
    check_choice("noise", name, PROFILES)
    return PROFILES[name]
