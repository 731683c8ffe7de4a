"""Resampling against closed forms: a base turning at a constant yaw rate while rising linearly and a
hinge swinging as a sine, sampled at 1 kHz and resampled to 30/50/77 fps, gives the closed-form
positions and quaternions at the frame times, and velocities (central differences of the frames)
exact for the linear motion and the constant yaw rate and within the Taylor bound A w^3 h^2 / 6 for
the sine; quaternion signs flipped in the source (the same rotations) change nothing, and the output
quaternions never flip sign."""

from __future__ import annotations

import numpy as np
import pytest

from gaitshift.errors import InputError
from gaitshift.export.resample import continuous_quaternions, frame_times, resample, slerp

W, A, F = 0.9, 0.4, 1.3  # yaw rate rad/s (turning more than a full turn), hinge amplitude rad, frequency Hz


def closed_form(t):
    """qpos (N, 8) and qvel (N, 7) of the free base plus one hinge."""
    yaw = W * t
    qpos = np.zeros((len(t), 8))
    qpos[:, 0], qpos[:, 2] = 0.3 * t, 0.7 + 0.05 * t
    qpos[:, 3], qpos[:, 6] = np.cos(yaw / 2), np.sin(yaw / 2)
    qpos[:, 7] = A * np.sin(2 * np.pi * F * t)
    qvel = np.zeros((len(t), 7))
    qvel[:, 0], qvel[:, 2], qvel[:, 5] = 0.3, 0.05, W
    qvel[:, 6] = A * 2 * np.pi * F * np.cos(2 * np.pi * F * t)
    return qpos, qvel


@pytest.mark.parametrize("fps", [30, 50, 77])
def test_resampling_reproduces_the_closed_form_at_the_frame_times(fps):
    t = np.arange(0, 8.0001, 0.001)
    qpos, _ = closed_form(t)
    flipped = qpos.copy()
    flipped[::3, 3:7] *= -1  # same rotations, other signs
    tau, q, v = resample(t, flipped, fps)
    exact_q, exact_v = closed_form(tau)
    assert np.allclose(np.diff(tau), 1 / fps) and tau[-1] <= t[-1] and tau[-1] > t[-1] - 1 / fps
    assert np.abs(q[:, :3] - exact_q[:, :3]).max() < 1e-12
    assert np.abs(np.abs(np.sum(q[:, 3:7] * exact_q[:, 3:7], axis=1)) - 1).max() < 1e-12  # slerp is exact here
    assert np.sum(q[1:, 3:7] * q[:-1, 3:7], axis=1).min() > 0  # continuous, although yaw passes 2 pi
    assert np.abs(q[:, 7] - exact_q[:, 7]).max() < (2 * np.pi * F) ** 2 * A * 1e-6 / 8 + 1e-12  # lerp error bound
    assert np.abs(v[:, :6] - exact_v[:, :6]).max() < 1e-9  # linear motion, constant yaw rate: exact
    taylor = A * (2 * np.pi * F) ** 3 / 6 / fps**2
    err = np.abs(v[1:-1, 6] - exact_v[1:-1, 6])
    assert err.max() < 1.05 * taylor + 1e-5 and err.max() > 0.5 * taylor  # the bound, and nearly reached


def test_slerp_halves_the_angle_and_takes_the_short_way():
    q0 = np.array([[1.0, 0, 0, 0]])
    q1 = -np.array([[np.cos(0.5), 0, 0, np.sin(0.5)]])  # a 1 rad yaw, negated
    mid = slerp(q0, q1, np.array([0.5]))
    assert np.allclose(mid, [[np.cos(0.25), 0, 0, np.sin(0.25)]])


def test_continuous_quaternions_keep_rotations_and_remove_flips():
    rng = np.random.default_rng(0)
    q = np.cumsum(rng.normal(scale=0.05, size=(200, 4)), axis=0) + np.array([1.0, 0, 0, 0])
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    signs = rng.choice([-1.0, 1.0], size=(200, 1))
    out = continuous_quaternions(q * signs)
    assert np.allclose(np.abs(np.sum(out * q, axis=1)), 1)
    assert np.sum(out[1:] * out[:-1], axis=1).min() > 0


def test_a_rate_too_low_for_two_frames_is_an_input_error():
    with pytest.raises(InputError, match="fps"):
        frame_times(np.array([0.0, 0.5]), 1)
