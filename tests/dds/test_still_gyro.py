"""The hold's gyro samples (``gaitshift.dds.still_gyro``): on the simulated G1 standing under a stiff PD and
pushed so that it rocks on its ankles (noise off: the gyro reads the true rate), the rate the legs' encoders
explain with both soles flat accounts for the gyro: the residual (the calibration's sample) is a small
fraction of the reading, and its mean, the bias estimate, is near zero while the readings' mean is not."""

import numpy as np

from gaitshift.control.frames import MotorCommand
from gaitshift.dds.still_gyro import LegRate
from gaitshift.robots.model import robot_model, standing_qpos
from gaitshift.sim.loop import SimOptions
from gaitshift.sim.plant import build_plant
from gaitshift.sim.world import World


def test_the_legs_explain_the_gyro_of_a_robot_rocking_on_its_feet():
    plant = build_plant(0.002, "g1")
    model = robot_model(plant.robot, 0.002)
    legs = LegRate(model.model, model.imu_site, tuple(plant.robot.sole_bodies), model.motor_names)
    world = World(plant, standing_qpos(plant), SimOptions(noise="none"), False, 1)
    frame = world.sense(0)
    n = len(frame.q)
    tau_max = np.where(np.isfinite(plant.robot.torque_limit), plant.robot.torque_limit, 50.0)
    hold = MotorCommand(q=frame.q.copy(), dq=np.zeros(n), kp=4.0 * tau_max, kd=0.1 * tau_max, tau=np.zeros(n))
    gyro, residual = [], []
    for k in range(500):
        world.observe(k)
        frame = world.sense(k)
        if k >= 100:  # the push is over; the robot rocks
            gyro.append(frame.imu_gyro)
            residual.append(legs.residual(frame.imu_gyro, frame.q, frame.dq))
        world.apply(hold, k)
        if k < 40:
            world.d.xfrc_applied[plant.pelvis_body, :3] = [60.0, 25.0, 0.0]  # N on the pelvis: it rocks
        world.step()
    gyro, residual = np.array(gyro), np.array(residual)
    assert np.abs(gyro).max() > 0.02  # it does rock (rad/s)
    assert np.sqrt(np.mean(residual**2)) < 0.1 * np.sqrt(np.mean(gyro**2))
    assert np.abs(residual.mean(axis=0)).max() < 0.1 * np.abs(gyro.mean(axis=0)).max()
