"""The hold's gyro calibration samples (``gaitshift.dds.still_gyro``), on the simulated G1 standing under a
stiff PD: pushed so that it rocks on its ankles (noise off: the gyro reads the true rate), the rate the
legs' joint angles explain (eq. (1)) accounts for the gyro, so the samples are a small fraction of the
readings and their mean, the bias estimate, is near zero while the readings' mean is not; with the
``typical`` sensors the calibration of a 2 s hold finds the gyro's true bias within its stated std, and
that std is the gyro's own noise over the hold, not the encoders'."""

import math

import numpy as np
import pytest

from gaitshift.control.estimation.calibration import GyroCalibration
from gaitshift.control.estimation.noise import PROFILES
from gaitshift.control.frames import MotorCommand
from gaitshift.dds.still_gyro import LegRate
from gaitshift.robots.model import robot_model, standing_qpos
from gaitshift.sim.loop import SimOptions
from gaitshift.sim.plant import build_plant
from gaitshift.sim.world import World

DT = 0.002


def stand(noise: str, push: tuple[float, float], ticks: int, seed: int = 0):
    """The G1 held at its standing pose by a stiff PD, pushed on the pelvis for its first 80 ms with ``push``
    (N, x and y); after 0.2 s, the readings (times, gyro, joint angles), the legs and the sensors' true bias."""
    plant = build_plant(DT, "g1")
    model = robot_model(plant.robot, DT)
    legs = LegRate(model.model, model.imu_site, tuple(plant.robot.sole_bodies), model.motor_names)
    world = World(plant, standing_qpos(plant), SimOptions(noise=noise, seed=seed), False, 1)
    frame = world.sense(0)
    n = len(frame.q)
    tau_max = np.where(np.isfinite(plant.robot.torque_limit), plant.robot.torque_limit, 50.0)
    hold = MotorCommand(q=frame.q.copy(), dq=np.zeros(n), kp=4.0 * tau_max, kd=0.1 * tau_max, tau=np.zeros(n))
    t, gyro, q = [], [], []
    for k in range(100 + ticks):
        world.observe(k)
        frame = world.sense(k)
        if k >= 100:
            t.append(k * DT)
            gyro.append(frame.imu_gyro)
            q.append(frame.q)
        world.apply(hold, k)
        if k < 40:
            world.d.xfrc_applied[plant.pelvis_body, :2] = push
        world.step()
    return np.array(t), np.array(gyro), np.array(q), legs, world.sensors.noise.gyro_bias


def test_the_legs_angles_explain_the_gyro_of_a_robot_rocking_on_its_feet():
    t, gyro, q, legs, _ = stand("none", (60.0, 25.0), 400)
    samples, period = legs.samples(t, gyro, q)
    assert np.abs(gyro).max() > 0.02  # it does rock (rad/s)
    assert period == pytest.approx(20 * DT) and len(samples) == 19
    assert np.sqrt(np.mean(samples**2)) < 0.1 * np.sqrt(np.mean(gyro**2))
    assert np.abs(samples.mean(axis=0)).max() < 0.1 * np.abs(gyro.mean(axis=0)).max()


def test_a_two_second_hold_finds_the_bias_within_the_gyros_own_noise():
    t, gyro, q, legs, bias = stand("typical", (0.0, 0.0), 1000, seed=1)
    cal = GyroCalibration.from_samples(*legs.samples(t, gyro, q))
    # the gyro's white noise averaged over the hold: density / sqrt(T) (1.7e-4 rad/s); the drivers' joint
    # speeds in eq. (1) instead gave samples whose spread stated 1.5e-3 rad/s (module docstring)
    own = PROFILES["typical"].gyro.density / math.sqrt(t[-1] - t[0])
    assert cal.std < 3.0 * own
    assert np.all(np.abs(cal.bias - bias) < 3.0 * cal.std)
