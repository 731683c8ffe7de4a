"""Synthetic walking for estimator checks and benchmarks: an analytic floating base with two point feet
(the tests of gaitshift.control.estimation, benchmarks/estimation.py).

Ground truth is closed-form, so the IMU signals are exact derivatives, not the output of an integrator
under test. The IMU frame is the base frame. With ZYX Euler angles ``(phi, theta, psi)`` (roll, pitch,
yaw), ``R = Rz(psi) Ry(theta) Rx(phi)`` and the body rates are (e.g. Stevens & Lewis, *Aircraft Control
and Simulation*, eq. 1.4-4)::

    w = (phi' - psi' sin(theta),
         theta' cos(phi) + psi' sin(phi) cos(theta),
         -theta' sin(phi) + psi' cos(phi) cos(theta))

Motion, period ``T`` = one step (``s = sin``, ``c = cos``)::

    x = u t + 0.02 s(2 pi t / T),  y = 0.04 s(pi t / T),  z = 0.72 + 0.01 c(2 pi t / T)
    phi = 0.04 s(pi t / T),  theta = 0.05 + 0.03 s(2 pi t / T),  psi = 0.25 s(2 pi t / 6 s)

Feet: foot i is in stance on ``[(2k + i) T - ds/2, (2k + i + 1) T + ds/2]`` (double support ``ds``),
fixed at ``(x(t_mid), +-0.1, 0)``; in swing it moves to the next foothold on a smoothstep in x and a
5 cm ``sin^2`` arc in z (zero velocity at lift-off and touchdown). The gyro and accelerometer are
sampled at the middle of each tick (the interval a filter integrates over), the accelerometer
expressed in the IMU frame at the start of that interval (the convention of :class:`ImuReading`);
the kinematics at the tick.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from gaitshift.control.estimation.noise import NoiseProfile
from gaitshift.control.estimation.types import FootKinematics, ImuReading
from gaitshift.sim.sensor_noise import SensorNoise

GRAVITY = 9.81


@dataclass(frozen=True)
class SyntheticWalk:
    """Ground truth sampled at ``t_k = k dt`` (IMU samples at ``t_k - dt/2``).

    Attributes:
        dt: tick period, s; t: (K,) times, s.
        rot: (K, 3, 3) base orientation; pos, vel: (K, 3) base position (m) and velocity (m/s).
        omega: (K, 3) body-frame angular velocity at t_k, rad/s.
        gyro: (K, 3) true body rate at ``t_k - dt/2``; accel: (K, 3) true specific force there, in the
            IMU frame at ``t_k - dt`` (:class:`ImuReading` convention).
        feet_world: (K, 2, 3) sole positions, m.
        feet_pos: (K, 2, 3) soles in the base frame; feet_vel: (K, 2, 3) their velocity relative to
            the base, in the base frame (what ``J qd`` gives), m/s.
        feet_rot: (K, 2, 3, 3) sole orientations in the base frame (soles flat, yawed like the base at
            mid-stance, turning on a smoothstep in swing).
        contact: (K, 2) stance flags.
    """

    dt: float
    t: np.ndarray
    rot: np.ndarray
    pos: np.ndarray
    vel: np.ndarray
    omega: np.ndarray
    gyro: np.ndarray
    accel: np.ndarray
    feet_world: np.ndarray
    feet_pos: np.ndarray
    feet_vel: np.ndarray
    feet_rot: np.ndarray
    contact: np.ndarray


def _euler(t: np.ndarray, step: float) -> tuple[np.ndarray, ...]:
    """Roll, pitch, yaw (K,) and their first derivatives."""
    a, b, c = np.pi / step, 2 * np.pi / step, 2 * np.pi / 6.0
    phi, dphi = 0.04 * np.sin(a * t), 0.04 * a * np.cos(a * t)
    theta, dtheta = 0.05 + 0.03 * np.sin(b * t), 0.03 * b * np.cos(b * t)
    psi, dpsi = 0.25 * np.sin(c * t), 0.25 * c * np.cos(c * t)
    return phi, theta, psi, dphi, dtheta, dpsi


def base_rotation(t: np.ndarray, step: float) -> np.ndarray:
    """``R(t) = Rz(psi) Ry(theta) Rx(phi)`` (K, 3, 3)."""
    phi, theta, psi, *_ = _euler(t, step)
    cf, sf, ct, st, cp, sp = np.cos(phi), np.sin(phi), np.cos(theta), np.sin(theta), np.cos(psi), np.sin(psi)
    return np.stack(
        [
            np.stack([cp * ct, cp * st * sf - sp * cf, cp * st * cf + sp * sf], -1),
            np.stack([sp * ct, sp * st * sf + cp * cf, sp * st * cf - cp * sf], -1),
            np.stack([-st, ct * sf, ct * cf], -1),
        ],
        -2,
    )


def body_rate(t: np.ndarray, step: float) -> np.ndarray:
    """Body-frame angular velocity (K, 3), rad/s (module docstring)."""
    phi, theta, _, dphi, dtheta, dpsi = _euler(t, step)
    return np.stack(
        [
            dphi - dpsi * np.sin(theta),
            dtheta * np.cos(phi) + dpsi * np.sin(phi) * np.cos(theta),
            -dtheta * np.sin(phi) + dpsi * np.cos(phi) * np.cos(theta),
        ],
        -1,
    )


def base_motion(t: np.ndarray, step: float, speed: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Base position, velocity and acceleration (K, 3)."""
    a, b = np.pi / step, 2 * np.pi / step
    pos = np.stack([speed * t + 0.02 * np.sin(b * t), 0.04 * np.sin(a * t), 0.72 + 0.01 * np.cos(b * t)], -1)
    vel = np.stack([speed + 0.02 * b * np.cos(b * t), 0.04 * a * np.cos(a * t), -0.01 * b * np.sin(b * t)], -1)
    acc = np.stack([-0.02 * b * b * np.sin(b * t), -0.04 * a * a * np.sin(a * t), -0.01 * b * b * np.cos(b * t)], -1)
    return pos, vel, acc


def feet_motion(
    t: np.ndarray, step: float, speed: float, double_support: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Sole positions and velocities in the world (K, 2, 3), sole yaws (K, 2) and stance flags (K, 2)."""
    yaw = np.zeros((t.size, 2))
    pos = np.zeros((t.size, 2, 3))
    vel = np.zeros((t.size, 2, 3))
    contact = np.zeros((t.size, 2), dtype=bool)
    half = 0.5 * double_support

    def foothold(k: np.ndarray) -> np.ndarray:  # x of the stance interval [k T - ds/2, (k+1) T + ds/2]
        tm = (k + 0.5) * step
        return speed * tm + 0.02 * np.sin(2 * np.pi * tm / step)

    def heading(k: np.ndarray) -> np.ndarray:  # sole yaw of that stance: the base yaw at mid-stance
        return _euler((k + 0.5) * step, step)[2]

    for i, side in enumerate((0.1, -0.1)):
        # stance k (same parity as i) covers [kT - half, (k+1)T + half]; swing to stance k + 2
        k = 2 * np.floor((t + half - i * step) / (2 * step)) + i  # latest stance start index
        into = t - (k * step - half)  # time since that stance began
        stance_len = step + double_support
        in_stance = into <= stance_len
        tau = np.clip((into - stance_len) / (2 * step - stance_len), 0.0, 1.0)
        x0, x1 = foothold(k), foothold(k + 2)
        s = 3 * tau**2 - 2 * tau**3
        ds = (6 * tau - 6 * tau**2) / (2 * step - stance_len)
        pos[:, i, 0] = np.where(in_stance, x0, x0 + s * (x1 - x0))
        pos[:, i, 1] = side
        pos[:, i, 2] = np.where(in_stance, 0.0, 0.05 * np.sin(np.pi * tau) ** 2)
        vel[:, i, 0] = np.where(in_stance, 0.0, ds * (x1 - x0))
        vel[:, i, 2] = np.where(in_stance, 0.0, 0.05 * np.pi * np.sin(2 * np.pi * tau) / (2 * step - stance_len))
        contact[:, i] = in_stance
        yaw[:, i] = np.where(in_stance, heading(k), heading(k) + s * (heading(k + 2) - heading(k)))
    return pos, vel, yaw, contact


def synthetic_walk(
    duration: float = 6.0, dt: float = 0.002, step: float = 0.4, speed: float = 0.5, double_support: float = 0.08
) -> SyntheticWalk:
    """Ground truth of the analytic walk (module docstring), ``duration`` s at period ``dt`` s."""
    t = np.arange(round(duration / dt) + 1) * dt
    rot = base_rotation(t, step)
    pos, vel, _ = base_motion(t, step, speed)
    tm = t - 0.5 * dt
    _, _, acc_m = base_motion(tm, step, speed)
    rot_start = base_rotation(t - dt, step)  # the IMU frame at the start of each tick's interval
    accel = np.einsum("kji,kj->ki", rot_start, acc_m + np.array([0.0, 0.0, GRAVITY]))  # R^T (a - g)
    feet_w, feet_v, yaw, contact = feet_motion(t, step, speed, double_support)
    zero, one = np.zeros_like(yaw), np.ones_like(yaw)
    rows = [[np.cos(yaw), -np.sin(yaw), zero], [np.sin(yaw), np.cos(yaw), zero], [zero, zero, one]]
    sole_world = np.stack([np.stack(r, -1) for r in rows], -2)  # (K, 2, 3, 3) Rz(yaw)
    omega = body_rate(t, step)
    rel = feet_w - pos[:, None, :]
    feet_pos = np.einsum("kji,kfj->kfi", rot, rel)  # R^T (d - p)
    feet_vel = np.einsum("kji,kfj->kfi", rot, feet_v - vel[:, None, :]) - np.cross(omega[:, None, :], feet_pos)
    return SyntheticWalk(
        dt=dt,
        t=t,
        rot=rot,
        pos=pos,
        vel=vel,
        omega=omega,
        gyro=body_rate(tm, step),
        accel=accel,
        feet_world=feet_w,
        feet_pos=feet_pos,
        feet_vel=feet_vel,
        feet_rot=np.einsum("kji,kfjl->kfil", rot, sole_world),  # R^T Z
        contact=contact,
    )


def synthetic_readings(
    walk: SyntheticWalk,
    profile: str | NoiseProfile = "typical",
    foot_pos_std: float = 0.002,
    foot_vel_std: float = 0.02,
    foot_rot_std: float = 0.01,
    seed: int = 0,
) -> tuple[list[ImuReading], list[FootKinematics], np.ndarray]:
    """Noisy sensor readings of a synthetic walk.

    The IMU follows the noise profile (:class:`SensorNoise`: white noise, turn-on bias and bias random
    walk); each sole position gets white noise of std ``foot_pos_std`` m per axis, its relative
    velocity ``foot_vel_std`` m/s per axis and its orientation ``Exp(n)``, ``n`` of std ``foot_rot_std``
    rad per axis (standing in for encoder and model error; the reported ``var`` and ``rot_var`` are
    0, the filter's ``foot_floor`` and ``foot_rot_floor`` carry it).

    Returns:
        imu readings (K,), foot kinematics (K,), and the true biases (K, 6) [gyro, accel] at each tick.
    """
    sensors = SensorNoise(profile, walk.dt, n_joints=0, weight=1.0, seed=seed)
    rng = np.random.default_rng(seed + 7919)
    k = walk.t.size
    pos = walk.feet_pos + rng.normal(0.0, foot_pos_std, walk.feet_pos.shape) if foot_pos_std > 0 else walk.feet_pos
    vel = walk.feet_vel + rng.normal(0.0, foot_vel_std, walk.feet_vel.shape) if foot_vel_std > 0 else walk.feet_vel
    rot = walk.feet_rot
    if foot_rot_std > 0:
        noise = Rotation.from_rotvec(rng.normal(0.0, foot_rot_std, (k * 2, 3))).as_matrix().reshape(k, 2, 3, 3)
        rot = np.einsum("kfij,kfjl->kfil", rot, noise)
    imu, feet, bias = [], [], np.zeros((k, 6))
    zero = np.zeros(2)
    for i in range(k):
        imu.append(sensors.imu(walk.gyro[i], walk.accel[i]))
        bias[i] = np.concatenate([sensors.gyro_bias, sensors.accel_bias])
        feet.append(FootKinematics(pos=pos[i], vel=vel[i], var=zero, rot=rot[i], rot_var=zero))
    return imu, feet, bias
