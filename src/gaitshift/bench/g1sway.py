"""A recorded G1 run for estimator checks and benchmarks: MuJoCo physics, the robot's own sensors, known
truth (the tests of gaitshift.control.estimation, gaitshift.bench.estimation, benchmarks/estimation.py).

The Unitree G1 (Menagerie ``scene.xml``: floor, the shipped ``kp = 500`` position servos) stands on
flat feet and sways: squat (knees 1.0 +- 0.15 rad at 0.5 Hz, ankles keeping the soles flat), lateral
weight shift (hip and ankle roll +- 0.015 rad at 0.7 Hz), torso yaw +- 0.1 rad at 0.4 Hz and
alternating arm swing (+- 0.2 rad at 0.9 Hz); it stays on both feet (no balance controller). The soles
stay flat within 0.016 rad but creep in yaw (0.05 rad peak to peak, MuJoCo's soft sphere contacts
under the torso's yaw reaction): a mild violation of the fixed-contact model, as on a real floor.

This is the simulator side, not the estimator: it reads MuJoCo's ``accelerometer`` sensor and the
angular velocity at ``imu_in_pelvis``, the joint ``qpos``/``qvel``, and the per-sole normal force as
the sum of ``mj_contactForce`` over the sole's contacts (a load cell would give it). A
:class:`SensorNoise` then turns them into readings. The estimator gets only those readings.

The IMU sample of tick k+1 is what an IMU that integrates internally (delta angle, delta velocity)
reports for the interval ``(t_k, t_k+1]``: the accelerometer value MuJoCo computes inside ``mj_step``
at the start of the interval and the angular velocity ``w_{k+1}`` that rotates ``R_k`` into ``R_{k+1}``
(semi-implicit Euler). The integrator is Euler, not the shipped ``implicitfast``: with the servos'
velocity feedback treated implicitly, ``v_{k+1} - v_k`` differs from ``dt qacc`` and the accelerometer
(built from ``qacc``) would disagree with the simulated motion. A sample taken after the step instead
(the next state, the old servo targets) disagrees by ~0.2-0.4 m/s^2 rms on this run: stiff contacts
and servo targets change the acceleration within one tick.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from gaitshift.control.estimation.noise import NoiseProfile
from gaitshift.control.estimation.types import FootForces, ImuReading, JointReading
from gaitshift.sim.sensor_noise import SensorNoise


@dataclass(frozen=True)
class RecordedRun:
    """Readings and truth of a simulated run, one entry per tick.

    Attributes:
        dt: tick period, s.
        qpos0, qvel0: the initial state (what ``StateEstimator.reset`` is given).
        imu, joints, forces: the noisy readings (K,).
        qpos, qvel: (K, nq), (K, nv) true MuJoCo state after each tick.
        com, com_vel: (K, 3) true whole-body CoM position and velocity.
        contact: (K, 2) true sole load above 5 % of the weight.
        foot_vel: (K, 2, 3) true world velocity of the two ankle-roll (foot) bodies, m/s.
    """

    dt: float
    qpos0: np.ndarray
    qvel0: np.ndarray
    imu: list[ImuReading]
    joints: list[JointReading]
    forces: list[FootForces]
    qpos: np.ndarray
    qvel: np.ndarray
    com: np.ndarray
    com_vel: np.ndarray
    contact: np.ndarray
    foot_vel: np.ndarray


def _sway_targets(t: float, stand: np.ndarray, index: dict[str, int]) -> np.ndarray:
    """Servo targets (nu,) at time ``t``: standing pose plus the sway of the module docstring."""
    target = stand.copy()
    squat = 0.15 * np.sin(2 * np.pi * 0.5 * t)
    roll = 0.015 * np.sin(2 * np.pi * 0.7 * t)
    for side, arm in (("left", 1.0), ("right", -1.0)):
        target[index[f"{side}_hip_pitch_joint"]] -= 0.5 * squat
        target[index[f"{side}_knee_joint"]] += squat
        target[index[f"{side}_ankle_pitch_joint"]] -= 0.5 * squat
        target[index[f"{side}_hip_roll_joint"]] += roll
        target[index[f"{side}_ankle_roll_joint"]] -= roll
        target[index[f"{side}_shoulder_pitch_joint"]] += arm * 0.2 * np.sin(2 * np.pi * 0.9 * t)
    target[index["waist_yaw_joint"]] += 0.1 * np.sin(2 * np.pi * 0.4 * t)
    return target


def _standing_scene(robot: Any, dt: float, slippery: int | None) -> tuple[Any, Any, np.ndarray, list[int]]:
    """The scene model (Euler, period ``dt``, optionally one slippery sole) and its data standing on
    the floor; also the servo targets of the standing pose (nu,) and the two foot body ids."""
    model = mujoco.MjSpec.from_file(str(Path(robot.mjcf).parent / "scene.xml")).compile()
    model.opt.timestep = dt
    model.opt.integrator = mujoco.mjtIntegrator.mjINT_EULER  # accelerometer consistent with the motion
    data = mujoco.MjData(model)
    names = [model.joint(model.actuator_trnid[a, 0]).name for a in range(model.nu)]
    pose = dict(robot.standing_pose)
    stand = np.array([pose.get(n, 0.0) for n in names])
    data.qpos[7:] = stand
    data.qpos[3:7] = (1.0, 0.0, 0.0, 0.0)
    mujoco.mj_kinematics(model, data)
    feet = [int(model.body(b).id) for b in robot.sole_bodies]
    foot_geoms = [np.flatnonzero(model.geom_bodyid == b) for b in feet]
    if slippery is not None:
        geoms = foot_geoms[slippery]
        model.geom_friction[geoms[model.geom_type[geoms] == mujoco.mjtGeom.mjGEOM_SPHERE], 0] = 0.05
    data.qpos[2] -= min(data.geom_xpos[g, 2].min() - model.geom_size[g, 0].max() for g in foot_geoms)
    mujoco.mj_forward(model, data)
    return model, data, stand, feet


def sole_normal_forces(model: Any, data: Any, feet: list[int]) -> np.ndarray:
    """Normal force (2,) N on each foot body: the sum of ``mj_contactForce`` over its contacts."""
    normal, wrench = np.zeros(2), np.zeros(6)
    for c in range(data.ncon):
        bodies = model.geom_bodyid[[data.contact[c].geom1, data.contact[c].geom2]]
        for side in (0, 1):
            if feet[side] in bodies:
                mujoco.mj_contactForce(model, data, c, wrench)
                normal[side] += wrench[0]
    return normal


def record_g1_sway(
    robot: Any,
    duration: float = 6.0,
    dt: float = 0.002,
    profile: str | NoiseProfile = "typical",
    seed: int = 0,
    slippery: int | None = None,
    push: tuple[float, float, float] | None = None,
) -> RecordedRun:
    """Simulate the G1 sway (module docstring) for ``duration`` s and record readings and truth.

    ``slippery``: 0 or 1, that sole's friction becomes 0.05 (from 0.6); ``push``: (start s, end s,
    force N) applied forward (+x) on that foot (or on the pelvis if no sole is slippery): it makes the
    slippery sole slide.
    """
    model, data, stand, feet = _standing_scene(robot, dt, slippery)
    index = {model.joint(model.actuator_trnid[a, 0]).name: a for a in range(model.nu)}
    qpos0, qvel0 = data.qpos.copy(), data.qvel.copy()
    accel = model.sensor("imu-pelvis-linear-acceleration").adr[0]
    site = model.site("imu_in_pelvis").id
    pushed = 1 if slippery is None else feet[slippery]
    weight = float(model.body_subtreemass[1]) * 9.81
    noise = SensorNoise(profile, dt, model.nu, weight, seed)
    out: dict[str, list[Any]] = {n: [] for n in ("imu", "joints", "forces", "qpos", "qvel", "com", "vel", "f", "fv")}
    twist = np.zeros(6)
    for i in range(round(duration / dt)):
        if push is not None:
            data.xfrc_applied[pushed, 0] = push[2] if push[0] <= i * dt < push[1] else 0.0
        data.ctrl[:] = _sway_targets(i * dt, stand, index)
        mujoco.mj_step(model, data)
        acc = data.sensordata[accel : accel + 3].copy()  # at the start of the tick: v_{k+1} = v_k + dt a_k
        mujoco.mj_forward(model, data)  # CoM and frames at the new state
        mujoco.mj_subtreeVel(model, data)
        rot_site = data.site_xmat[site].reshape(3, 3)
        rate = rot_site.T @ data.xmat[1].reshape(3, 3) @ data.qvel[3:6]  # the rate that took R_k to R_{k+1}
        normal = sole_normal_forces(model, data, feet)
        out["imu"].append(noise.imu(rate, acc))
        out["joints"].append(noise.joints(data.qpos[7:], data.qvel[6:]))
        out["forces"].append(noise.forces(normal))
        out["qpos"].append(data.qpos.copy())
        out["qvel"].append(data.qvel.copy())
        out["com"].append(data.subtree_com[1].copy())
        out["vel"].append(data.subtree_linvel[1].copy())
        out["f"].append(normal)
        foot_vel = []
        for b in feet:
            mujoco.mj_objectVelocity(model, data, mujoco.mjtObj.mjOBJ_BODY, b, twist, 0)
            foot_vel.append(twist[3:6].copy())
        out["fv"].append(foot_vel)
    return RecordedRun(
        dt=dt,
        qpos0=qpos0,
        qvel0=qvel0,
        imu=out["imu"],
        joints=out["joints"],
        forces=out["forces"],
        qpos=np.array(out["qpos"]),
        qvel=np.array(out["qvel"]),
        com=np.array(out["com"]),
        com_vel=np.array(out["vel"]),
        contact=np.array(out["f"]) > 0.05 * weight,
        foot_vel=np.array(out["fv"]),
    )
