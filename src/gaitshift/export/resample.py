"""Resampling a configuration trajectory to new frame times.

A trajectory is sampled at times ``t`` (N,), increasing, with MuJoCo configurations ``qpos`` (N, nq)
of a floating-base robot (free joint first: x, y, z, qw, qx, qy, qz) and velocities ``qvel`` (N, nv)
(free joint: world linear velocity of the base origin, then body-frame angular velocity). At a frame
time tau in [t_i, t_{i+1}] with w = (tau - t_i) / (t_{i+1} - t_i):

* positions and hinge angles are interpolated linearly, x(tau) = (1 - w) x_i + w x_{i+1};
* the base quaternion by slerp, q(tau) = q_i (q_i^-1 q_{i+1})^w, on the source quaternions made
  continuous first (q_{i+1} -> -q_{i+1} whenever q_i . q_{i+1} < 0, the same rotation), so that the
  result has no sign flip either;
* velocities linearly, v(tau) = (1 - w) v_i + w v_{i+1}: the velocity of the source at its own rate
  (measured, or central differences of the IK solution), so that the exported velocities are the
  derivative of the exported positions up to the interpolation error, O(dt_source^2), and the
  central-difference error at the output rate, O(1/fps^2).
"""

from __future__ import annotations

import numpy as np

from gaitshift.errors import InputError


def continuous_quaternions(q: np.ndarray) -> np.ndarray:
    """Quaternions (..., N, 4) with signs chosen so that consecutive ones have a non-negative dot
    product along axis -2 (each one keeps its rotation; the first keeps its sign)."""
    q = np.array(q, dtype=float, copy=True)
    if q.shape[-2] < 2:
        return q
    dots = np.sum(q[..., 1:, :] * q[..., :-1, :], axis=-1)
    flips = np.concatenate([np.zeros((*dots.shape[:-1], 1), int), np.cumsum(dots < 0, axis=-1)], axis=-1)
    q[flips % 2 == 1] *= -1.0
    return q


def slerp(q0: np.ndarray, q1: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Spherical linear interpolation between unit quaternions (N, 4) at weights w (N,), the shorter
    way round (q1 is negated where q0 . q1 < 0); unit quaternions (N, 4) out."""
    dot = np.sum(q0 * q1, axis=-1)
    q1 = np.where(dot[:, None] < 0, -q1, q1)
    dot = np.abs(dot)
    theta = np.arccos(np.clip(dot, -1.0, 1.0))
    small = theta < 1e-8
    s = np.sin(np.where(small, 1.0, theta))
    a = np.where(small, 1.0 - w, np.sin((1.0 - w) * theta) / s)
    b = np.where(small, w, np.sin(w * theta) / s)
    out = a[:, None] * q0 + b[:, None] * q1
    out /= np.linalg.norm(out, axis=-1, keepdims=True)
    return np.asarray(out, dtype=float)


def frame_times(t: np.ndarray, fps: float) -> np.ndarray:
    """Frame times t_0 + k / fps, k = 0, 1, ..., up to the last source time (s).

    Raises:
        InputError: fewer than 2 frames fit.
    """
    n = int(np.floor((t[-1] - t[0]) * fps + 1e-9)) + 1
    if n < 2:
        raise InputError("fps", fps, f"a rate giving at least 2 frames over the {t[-1] - t[0]:.3f} s motion")
    return np.asarray(t[0] + np.arange(n) / fps, dtype=float)


def resample(
    t: np.ndarray, qpos: np.ndarray, qvel: np.ndarray, fps: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(times (F,), qpos (F, nq), qvel (F, nv)) at ``fps`` Hz from the source samples (see module
    docstring); the base quaternion of the result is continuous."""
    tau = frame_times(t, fps)
    i = np.clip(np.searchsorted(t, tau, side="right") - 1, 0, len(t) - 2)
    w = np.clip((tau - t[i]) / (t[i + 1] - t[i]), 0.0, 1.0)
    quats = continuous_quaternions(qpos[:, 3:7])
    out_q = (1.0 - w)[:, None] * qpos[i] + w[:, None] * qpos[i + 1]
    out_q[:, 3:7] = continuous_quaternions(slerp(quats[i], quats[i + 1], w))
    out_v = (1.0 - w)[:, None] * qvel[i] + w[:, None] * qvel[i + 1]
    return tau, out_q, out_v
