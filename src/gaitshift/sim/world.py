"""The simulated world: the plant's truth, its sensors, the link to the motors, pushes, the fall test.

This is the only code, with the metrics, that reads the plant's ``MjData``. Per tick::

    world.observe(k)        latch the IMU over the last step, mj_forward, the true contacts, the fall test
    frame = world.sense(k)  SensorFrame: IMU (quaternion, gyro, accelerometer), encoders, driver
                            velocities, motor torques, sole forces, all in motor order, corrupted by
                            the noise profile; the depth camera's points (its frames only,
                            gaitshift.sim.depth_camera); the oracle's OracleState only when asked for
    world.apply(cmd, k)     tau + kp (q - q_meas) + kd (dq - dq_meas) per motor, through the latency
                            pipe, into the plant (the only write), and the push of tick k
    mujoco.mj_step

Nothing of the plant reaches the controller but the frame: its arrays are copies.
"""

from __future__ import annotations

import copy
from dataclasses import replace
from typing import Any

import mujoco
import numpy as np

from gaitshift.control.estimation.calibration import CALIBRATION_TIME
from gaitshift.control.estimation.noise import noise_profile
from gaitshift.control.frames import MotorCommand, OracleState, SensorFrame
from gaitshift.control.settings import contact_source
from gaitshift.models.terrain import Terrain
from gaitshift.sim.contacts import ContactSensor, FootContacts, fall_reason
from gaitshift.sim.depth_camera import DepthCameraSim
from gaitshift.sim.latency import CommandDelay
from gaitshift.sim.perturb import perturbed_physics, with_joint_vel_noise
from gaitshift.sim.plant import Plant
from gaitshift.sim.pushes import push_forces
from gaitshift.sim.sensors import Readings, SensorModel

__all__ = ["World", "with_floor_friction"]


def with_floor_friction(plant: Any, mu: float | None) -> Any:
    """The plant with a copy of its model whose floor (and bumps) set the contact friction to ``mu`` (sliding;
    MuJoCo uses the friction of the geom of higher ``priority``, so the floor gets priority 1), or the
    plant itself when ``mu`` is None."""
    if mu is None:
        return plant
    model = copy.copy(plant.model)
    ground = list(getattr(plant, "ground_geoms", ()) or (plant.floor_geom,))  # the floor, the terrain and the bumps
    model.geom_priority[ground] = int(model.geom_priority.max()) + 1
    model.geom_friction[ground, 0] = float(mu)
    return replace(plant, model=model)


class World:
    """One run's world (module docstring).

    Args:
        plant: the simulated plant (its model: the nominal robot; the physics steps a mass-scaled copy).
        qpos0: the start state (nq,), at rest.
        opts: the run's :class:`~gaitshift.sim.loop.SimOptions` (noise, seed, latency, mass scale, pushes).
        oracle: put the truth into every frame (the controller acts on the oracle).
        n_ticks: ticks of the run (the pushes' table).
        depth_camera: cast the robot's depth camera (when its YAML has one); a host whose link carries
            no depth frames (Unitree's ``LowState_``) leaves it off.
    """

    def __init__(
        self, plant: Plant, qpos0: np.ndarray, opts: Any, oracle: bool, n_ticks: int, depth_camera: bool = True
    ) -> None:
        self.plant, self.opts, self.oracle = plant, opts, oracle
        # the truth; the controller keeps the nominal model
        self.physics = perturbed_physics(
            plant.model, opts.mass_scale, opts.com_offset, opts.motor_strength, plant.pelvis_body
        )
        self.d = mujoco.MjData(plant.model)
        self.d.qpos[:] = qpos0
        mujoco.mj_forward(plant.model, self.d)
        self.dt = plant.dt
        m = plant.model
        profile = noise_profile(opts.noise).scaled(float(opts.noise_scale))
        # the extra joint-velocity noise reaches the sensors only: the estimator is tuned to the profile
        self.sensors = SensorModel(m, with_joint_vel_noise(profile, opts.joint_vel_noise), opts.seed, plant.imu)
        self.imu_site = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, plant.imu)
        self.foot_force = contact_source(opts.contact, plant.robot) == "force"  # the robot has sole sensors
        joints = m.actuator_trnid[:, 0]
        self.motor_q = m.jnt_qposadr[joints] - 7  # motor -> index into the joint arrays (qpos[7:], qvel[6:])
        self.motor_v = m.jnt_dofadr[joints] - 6
        self.delay = CommandDelay(opts.latency)
        self.contact_sensor = ContactSensor(plant)
        cam = plant.robot.sensors.depth_camera
        self.camera = None if cam is None or not depth_camera else DepthCameraSim(m, cam, self.dt, opts.seed)
        self.ground = Terrain.from_list(None)
        self.pelvis0 = float(qpos0[2])
        self.push = push_forces(opts.pushes, opts.settle, self.dt, n_ticks)
        self.contacts: FootContacts | None = None
        self.applied = np.zeros(m.nu)
        self._twist = np.zeros(6)

    def on_ground(self, ground: Terrain) -> None:
        """The ground the fall test measures the pelvis height above."""
        self.ground = ground
        q0 = self.d.qpos
        self.pelvis0 = float(q0[2] - ground.height(q0[0]))

    def still_gyro(self, seconds: float = CALIBRATION_TIME) -> np.ndarray:
        """Gyro readings (N, 3) rad/s of the robot standing still before the run (the calibration)."""
        return self.sensors.still_gyro(seconds)

    def observe(self, k: int) -> str | None:
        """Tick ``k``: bring the truth up to date; the fall's reason, or None."""
        m, d = self.physics, self.d
        if k > 0:
            self.sensors.latch(d)
        mujoco.mj_forward(m, d)
        mujoco.mj_subtreeVel(m, d)
        self.contacts = self.contact_sensor.read(d)  # truth: the metrics and the fall test
        return fall_reason(self.contacts, float(d.qpos[2] - self.ground.height(d.qpos[0])), self.pelvis0)

    def sense(self, k: int) -> SensorFrame:
        """The frame of tick ``k`` (after :meth:`observe`): what the robot reports, in motor order."""
        d = self.d
        r: Readings = self.sensors.exact(d) if k == 0 else self.sensors.read(d)
        quat = np.empty(4)
        mujoco.mju_mat2Quat(quat, d.site_xmat[self.imu_site])
        return SensorFrame(
            t=k * self.dt,
            imu_quat=quat,
            imu_gyro=r.imu.gyro,
            imu_acc=r.imu.accel,
            q=r.joints.q[self.motor_q],
            dq=r.joints.qd[self.motor_v],
            tau_est=d.actuator_force.copy(),
            foot_force=r.forces.normal if self.foot_force else None,
            depth_points=None if self.camera is None else self.camera.read(d, k),
            oracle=self._truth() if self.oracle else None,
        )

    def _truth(self) -> OracleState:
        d, contacts = self.d, self.contacts
        assert contacts is not None
        vel = np.zeros((2, 2))
        for s, sole in enumerate(self.plant.soles):
            mujoco.mj_objectVelocity(self.plant.model, d, mujoco.mjtObj.mjOBJ_BODY, sole.body, self._twist, 0)
            vel[s] = self._twist[3:5]
        return OracleState(qpos=d.qpos.copy(), qvel=d.qvel.copy(), contact=contacts.touching.copy(), sole_velocity=vel)

    def apply(self, cmd: MotorCommand, k: int) -> np.ndarray:
        """Send ``cmd`` through the link (eq. (1) of :mod:`gaitshift.control.frames` at the motors' own
        encoders, the latency pipe) and the push of tick ``k``; returns the torques acting now (nu,)."""
        d = self.d
        tau = cmd.torques(d.qpos[7:][self.motor_q], d.qvel[6:][self.motor_v])
        self.applied = self.delay.send(tau)
        d.ctrl[:] = self.applied
        push = self.push[k] if k < len(self.push) else np.zeros(3)
        d.xfrc_applied[self.plant.pelvis_body, :3] = push
        return push

    def step(self) -> None:
        """Advance the physics one period."""
        mujoco.mj_step(self.physics, self.d)
