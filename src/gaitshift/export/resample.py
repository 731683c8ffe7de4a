"""Resampling a configuration trajectory to new frame times.

A trajectory is sampled at times ``t`` (N,), increasing, with MuJoCo configurations ``qpos`` (N, nq)
of a floating-base robot (free joint first: x, y, z, qw, qx, qy, qz; then one coordinate per hinge).
At a frame time tau in [t_i, t_{i+1}] with w = (tau - t_i) / (t_{i+1} - t_i):

* positions and hinge angles are interpolated linearly, x(tau) = (1 - w) x_i + w x_{i+1};
* the base quaternion by slerp, q(tau) = q_i (q_i^-1 q_{i+1})^w, on the source quaternions made
  continuous first (q_{i+1} -> -q_{i+1} whenever q_i . q_{i+1} < 0, the same rotation), so that the
  result has no sign flip either.

The velocities (MuJoCo qvel layout: world linear velocity of the base, its body-frame angular
velocity, the hinge rates) are the central differences of the resampled frames, h = 1/fps:
v_k = (x_{k+1} - x_{k-1}) / 2h, omega_k = log(q_{k-1}^-1 q_{k+1}) / 2h, one-sided at both ends, as
mjlab's ``csv_to_npz`` derives them (``torch.gradient`` and an SO(3) difference). The exported
velocities are then the derivative of the exported positions, exact at the frame rate (a velocity
step of the source, an impact or a kink of the IK, is spread over two frames instead of appearing
as a value that no difference of the positions reproduces); they are within O(h^2) of the source's
own velocity elsewhere.
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


def rotation_vector(q: np.ndarray) -> np.ndarray:
    """Rotation vectors (..., 3) of unit quaternions (..., 4) (w first), the shorter way round."""
    q = np.where(q[..., :1] < 0, -q, q)
    s = np.linalg.norm(q[..., 1:], axis=-1)
    angle = 2.0 * np.arctan2(s, q[..., 0])
    return np.asarray(q[..., 1:] * np.where(s > 1e-12, angle / np.maximum(s, 1e-300), 2.0)[..., None], dtype=float)


def relative_quaternion(q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """q0^-1 q1 (..., 4) of unit quaternions (w first)."""
    w0, v0 = q0[..., :1], -q0[..., 1:]
    w1, v1 = q1[..., :1], q1[..., 1:]
    return np.concatenate([w0 * w1 - np.sum(v0 * v1, -1, keepdims=True), w0 * v1 + w1 * v0 + np.cross(v0, v1)], -1)


def central_velocities(qpos: np.ndarray, h: float) -> np.ndarray:
    """qvel (F, nq - 1) of frames ``qpos`` (F, nq) ``h`` s apart: central differences (see module
    docstring), one-sided at the ends."""
    n = len(qpos)
    lo, hi = np.r_[0, np.arange(n - 2), n - 2], np.r_[1, np.arange(2, n), n - 1]
    span = (hi - lo)[:, None] * h
    v = np.empty((n, qpos.shape[1] - 1))
    v[:, 0:3] = (qpos[hi, 0:3] - qpos[lo, 0:3]) / span
    v[:, 3:6] = rotation_vector(relative_quaternion(qpos[lo, 3:7], qpos[hi, 3:7])) / span
    v[:, 6:] = (qpos[hi, 7:] - qpos[lo, 7:]) / span
    return v


def resample(t: np.ndarray, qpos: np.ndarray, fps: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(times (F,), qpos (F, nq), qvel (F, nv)) at ``fps`` Hz from the source samples (see module
    docstring); the base quaternion of the result is continuous."""
    tau = frame_times(t, fps)
    i = np.clip(np.searchsorted(t, tau, side="right") - 1, 0, len(t) - 2)
    w = np.clip((tau - t[i]) / (t[i + 1] - t[i]), 0.0, 1.0)
    quats = continuous_quaternions(qpos[:, 3:7])
    out_q = (1.0 - w)[:, None] * qpos[i] + w[:, None] * qpos[i + 1]
    out_q[:, 3:7] = continuous_quaternions(slerp(quats[i], quats[i + 1], w))
    return tau, out_q, central_velocities(out_q, 1.0 / fps)
