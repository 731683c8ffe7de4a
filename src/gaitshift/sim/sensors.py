"""The sensor model: what the simulated robot senses, read from the plant, corrupted by a noise profile.

This is the only code, with the metrics, that reads the plant's ``MjData`` for control purposes. Per
tick it gives the estimator (:mod:`gaitshift.control.estimation`):

* an IMU sample of the interval ``(t_{k-1}, t_k]`` from the model's own sensors at the IMU site
  (the G1's ``imu_in_pelvis`` gyro and accelerometer): the accelerometer as ``mj_step`` left it in
  ``sensordata`` (computed at the start of the interval, with the command that drove it: ``v_k =
  v_{k-1} + dt a_{k-1}``), latched by :meth:`SensorModel.latch` before the next ``mj_forward``; the
  gyro after that ``mj_forward`` (the rate ``w_k`` that rotated ``R_{k-1}`` into ``R_k``: MuJoCo
  integrates positions with the new velocity). This is what a delta-angle / delta-velocity IMU
  reports (docs/estimation.md, "IMU timing");
* joint encoders (position, quantised, noisy) and the velocity a motor driver reports (for the
  ``typical`` profile the difference of two encoder readings over one tick), in the model's joint
  order (``qpos[7:]``, ``qvel[6:]``);
* one normal-force signal per sole from the ``touch`` sensors of :mod:`gaitshift.sim.sensor_spec`
  (never MuJoCo's contact list).

Noise, biases and quantisation follow a :class:`~gaitshift.control.estimation.noise.NoiseProfile`
scaled by ``noise_scale`` (:meth:`NoiseProfile.scaled`); every draw comes from one generator seeded
with the run's seed.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np

from gaitshift.control.estimation.noise import NoiseProfile
from gaitshift.control.estimation.types import FootForces, ImuReading, JointReading
from gaitshift.errors import InputError
from gaitshift.sim.sensor_noise import SensorNoise
from gaitshift.sim.sensor_spec import SOLE_TOUCH_SENSORS


@dataclass(frozen=True)
class Readings:
    """What the robot senses at one tick (already corrupted by the noise profile)."""

    imu: ImuReading
    joints: JointReading
    forces: FootForces


def _sensor_adr(model: Any, site: int, kind: Any) -> int:
    """``sensordata`` address of the sensor of type ``kind`` attached to site ``site``."""
    for i in range(model.nsensor):
        on_site = model.sensor_objtype[i] == mujoco.mjtObj.mjOBJ_SITE and model.sensor_objid[i] == site
        if model.sensor_type[i] == kind and on_site:
            return int(model.sensor_adr[i])
    name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_SITE, site)
    raise InputError("imu_site", name, f"a site with a {kind.name} sensor")


class SensorModel:
    """Reads :class:`Readings` from the plant's ``MjData`` (see module docstring).

    Args:
        model: the plant's ``MjModel`` (with the sole touch sensors).
        profile: the sensors' noise profile (already scaled).
        seed: the run's seed.
        imu_site: name of the IMU site carrying a gyro and an accelerometer.
    """

    def __init__(self, model: Any, profile: NoiseProfile, seed: int, imu_site: str) -> None:
        site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, imu_site)
        if site < 0:
            raise InputError("imu_site", imu_site, "a site of the robot model")
        self.gyro_adr = _sensor_adr(model, site, mujoco.mjtSensor.mjSENS_GYRO)
        self.accel_adr = _sensor_adr(model, site, mujoco.mjtSensor.mjSENS_ACCELEROMETER)
        self.touch_adr = np.array([model.sensor(n).adr[0] for n in SOLE_TOUCH_SENSORS])
        nj = model.nq - 7
        weight = float(model.body_subtreemass[0]) * -float(model.opt.gravity[2])
        self.noise = SensorNoise(profile, float(model.opt.timestep), nj, weight, seed)
        self._accel: np.ndarray | None = None

    def still_gyro(self, seconds: float) -> np.ndarray:
        """Gyro readings (N, 3) rad/s of a robot that stands still for ``seconds`` before the run (true
        rate zero; the biases walk on meanwhile): the samples of a standstill calibration. The
        accelerometer readings drawn alongside are discarded."""
        n = max(2, round(seconds / self.noise.dt))
        zero = np.zeros(3)
        return np.array([self.noise.imu(zero, zero).gyro for _ in range(n)])

    def latch(self, d: Any) -> None:
        """Keep the accelerometer value ``mj_step`` computed (call after the step, before ``mj_forward``)."""
        self._accel = d.sensordata[self.accel_adr : self.accel_adr + 3].copy()

    def exact(self, d: Any) -> Readings:
        """The readings of ``d`` (after ``mj_forward``) without noise and without a draw: the first frame
        of a run, the known start state at rest (the controller starts from that state, so the noise
        stream starts with the second tick)."""
        gyro = d.sensordata[self.gyro_adr : self.gyro_adr + 3].copy()
        accel = d.sensordata[self.accel_adr : self.accel_adr + 3].copy()
        return Readings(
            imu=ImuReading(gyro=gyro, accel=accel),
            joints=JointReading(q=d.qpos[7:].copy(), qd=d.qvel[6:].copy()),
            forces=FootForces(normal=d.sensordata[self.touch_adr].copy()),
        )

    def read(self, d: Any) -> Readings:
        """The readings of the current tick (``d`` after ``mj_forward``)."""
        gyro = d.sensordata[self.gyro_adr : self.gyro_adr + 3]
        accel = self._accel if self._accel is not None else d.sensordata[self.accel_adr : self.accel_adr + 3]
        return Readings(
            imu=self.noise.imu(gyro, accel),
            joints=self.noise.joints(d.qpos[7:], d.qvel[6:]),
            forces=self.noise.forces(d.sensordata[self.touch_adr]),
        )
