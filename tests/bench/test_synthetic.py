"""The synthetic walk is a valid ground truth: its gyro integrates to its rotations and its
accelerometer to its velocities (checked with scipy and finite differences, not the filters), stance
soles stay put in the world, and the soles' base-frame kinematics are consistent with the base motion."""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from gaitshift.bench.synthetic import synthetic_walk

G = np.array([0.0, 0.0, -9.81])


def test_gyro_samples_rotate_each_orientation_into_the_next():
    w = synthetic_walk(2.0)
    step = Rotation.from_rotvec(w.gyro[1:] * w.dt).as_matrix()
    predicted = w.rot[:-1] @ step
    err = [np.linalg.norm(Rotation.from_matrix(p @ r.T).as_rotvec()) for p, r in zip(predicted, w.rot[1:], strict=True)]
    assert max(err) < 1e-7  # midpoint rule, O(dt^3) per tick


def test_accelerometer_samples_integrate_to_the_velocity():
    w = synthetic_walk(2.0)
    acc_world = np.einsum("kij,kj->ki", w.rot[:-1], w.accel[1:]) + G  # start-of-tick frame (ImuReading)
    np.testing.assert_allclose(w.vel[:-1] + acc_world * w.dt, w.vel[1:], atol=1e-6)


def test_stance_soles_stay_put_and_kinematics_match_the_base_motion():
    w = synthetic_walk(2.0)
    for i in (0, 1):
        held = w.contact[:-1, i] & w.contact[1:, i]
        assert np.abs(np.diff(w.feet_world[:, i], axis=0)[held]).max() == 0.0
    seen = np.einsum("kij,kfj->kfi", w.rot, w.feet_pos) + w.pos[:, None, :]
    np.testing.assert_allclose(seen, w.feet_world, atol=1e-12)
    rate = np.diff(w.feet_pos, axis=0) / w.dt  # finite difference of the base-frame soles
    np.testing.assert_allclose(rate, 0.5 * (w.feet_vel[1:] + w.feet_vel[:-1]), atol=2e-3)
    assert w.contact.any(axis=1).all()  # walking: always a foot down
