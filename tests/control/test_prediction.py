"""The latency and age prediction (gaitshift.control.prediction): a frame ``a`` ticks old with a loop latency
``L`` is carried across the last ``L + a`` commands sent, by MuJoCo's own semi-implicit Euler (eq. (1))."""

from __future__ import annotations

import numpy as np
import pytest

from gaitshift.control.prediction import LatencyPredictor
from gaitshift.robots.model import standing_qpos
from gaitshift.sim.plant import build_plant


@pytest.mark.parametrize("latency", [0, 2])
def test_a_frame_a_ticks_old_is_carried_across_the_last_latency_plus_age_commands(latency):
    """Commands k = 0..7 planned the joint accelerations k rad/s^2 each; from rest, n = L + a of them give
    v = dt sum(qdd) and q - q0 = dt^2 sum_j (n - j) qdd_j (eq. (1), semi-implicit), on every hinge joint."""
    plant = build_plant()
    m, dt = plant.model, plant.model.opt.timestep
    pred = LatencyPredictor(m, latency, max_age=4)
    for k in range(8):
        pred.sent(np.full(m.nv, float(k)))
    q0, v0 = standing_qpos(plant), np.zeros(m.nv)
    for age in range(5):
        n = latency + age
        acc = np.arange(8 - n, 8, dtype=float)  # the last n commands' accelerations, oldest first
        q, v = pred.predict(q0, v0, age)
        np.testing.assert_allclose(v[6:], dt * acc.sum())
        np.testing.assert_allclose(q[7:] - q0[7:], dt * dt * np.sum((n - np.arange(n)) * acc), atol=1e-15)
    if latency == 0:  # a fresh frame and no latency: nothing to carry across, the state as measured
        assert pred.predict(q0, v0, 0)[0] is q0


def test_an_age_beyond_the_commands_kept_uses_all_of_them():
    """Before the first command the state is as measured; after it the window starts full of the first
    command planned at rest (zeros), so an age past the commands sent carries across zeros."""
    m = build_plant().model
    pred = LatencyPredictor(m, 1, max_age=3)
    q0, v0 = np.zeros(m.nq), np.ones(m.nv)
    assert pred.predict(q0, v0, 3)[1] is v0
    pred.sent(np.full(m.nv, 2.0))
    _, v = pred.predict(q0, v0, 3)  # 4 commands: three zeros and one of 2 rad/s^2
    np.testing.assert_allclose(v, 1.0 + m.opt.timestep * 2.0)
