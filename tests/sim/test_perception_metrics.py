"""The map's error under the feet counts what the logs say: stance ticks with a seen cell only, the
error against the true sole height, and in the controller's frame the estimate's base-height error
taken out."""

from __future__ import annotations

import numpy as np
import pytest

from gaitshift.sim.perception_metrics import perception_metrics


def test_the_error_is_measured_on_seen_stance_cells_and_the_frame_error_removes_the_drift():
    n = 100
    feet = np.zeros((n, 2, 3))
    feet[:, 1, 2] = 0.1  # the right sole stands on a 10 cm tread
    contact = np.ones((n, 2), bool)
    contact[:10, 0] = False  # the left sole swings for 10 ticks: not counted
    drift = -0.02  # the estimate's base is 2 cm low, so the map (placed with it) is 2 cm low too
    height = feet[:, :, 2] + drift + np.array([0.001, -0.003])
    known = np.ones((n, 2), bool)
    known[:20, 1] = False  # the right sole's cell unseen for 20 ticks: not counted
    qpos = np.zeros((n, 7))
    qpos[:, 2] = 0.75
    est = qpos.copy()
    est[:, 2] += drift
    a = {"contact": contact, "map_height": height, "map_known": known, "foot_pos": feet, "qpos": qpos, "est_qpos": est}
    p = perception_metrics(a, frames=7)["perception"]
    assert p["frames"] == 7 and p["map_coverage"] == pytest.approx((90 + 80) / (90 + 100))
    errs = np.r_[np.full(90, 0.019), np.full(80, 0.023)]
    assert p["map_error_median"] == pytest.approx(np.median(errs)) and p["map_error_p95"] == pytest.approx(0.023)
    assert p["frame_error_median"] == pytest.approx(0.001) and p["frame_error_p95"] == pytest.approx(0.003)
    assert perception_metrics({"contact": contact}, 0) == {}
