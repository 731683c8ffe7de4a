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


def test_a_stance_is_a_contact_of_at_least_min_stance_and_counts_at_its_middle():
    from gaitshift.sim.perception_metrics import MIN_STANCE, stances

    dt = 0.01
    c = np.zeros((40, 2), bool)
    c[0:10, 0] = True  # 0.10 s: a stance, middle tick 4
    c[20:22, 0] = True  # 0.02 s: a toe scuffing in a swing
    c[30:40, 1] = True  # runs to the end: middle tick 34
    m = stances(c, dt)
    assert MIN_STANCE <= 0.1
    assert np.flatnonzero(m[:, 0]).tolist() == [4] and np.flatnonzero(m[:, 1]).tolist() == [34]


def test_edge_distance_is_measured_from_the_true_sole_to_the_nearest_step_edge():
    from gaitshift.models.terrain import Piece, Terrain
    from gaitshift.sim.perception_metrics import edge_distances

    ground = Terrain(
        (Piece(1.0, 1.25, 0.1, 0.1), Piece(1.25, 3.0, 0.0, 0.0), Piece(3.0, 4.0, 0.0, 0.2), Piece(4.0, 9.0, 0.2, 0.2))
    )
    at = np.array([[True, False], [False, True], [True, False]])
    x = np.array([[1.13, 9.0], [0.0, 2.9], [0.5, 0.0]])
    xy = np.stack([x, np.zeros_like(x)], axis=-1)
    d = edge_distances(at, xy, ground, (0.17, 0.05))
    # 1.13: 0.12 from the edge at 1.25; 2.9: 1.65 from 1.25 (the ramp's foot at 3.0 and its top at 4.0 are
    # no step edges); 0.5: 0.5 from 1.0; less half the sole
    expect = np.array([0.12, 1.65, 0.5]) - 0.085
    assert d["edge_distance_min"] == pytest.approx(expect.min())
    assert d["edge_distance_median"] == pytest.approx(np.median(expect))
    assert edge_distances(at, xy, Terrain(), (0.17, 0.05)) == {}


def test_edge_distance_on_blocks_is_the_gap_to_the_nearest_side_of_a_block_in_the_plane():
    from gaitshift.models.blocks import Blocks
    from gaitshift.models.terrain import Piece, Terrain
    from gaitshift.sim.perception_metrics import edge_distances

    ground = Terrain(
        (Piece(1.0, 2.2, 0.04, 0.04, Blocks(0.4, 0.04, 3, 0.6)),)
    )  # x lines 1.0 1.4 1.8 2.2; y -0.6 -0.2 0.2 0.6
    at = np.ones((1, 2), bool)
    xy = np.array([[[1.6, 0.1], [1.25, -0.4]]])
    d = edge_distances(at, xy, ground, (0.17, 0.05))
    # left: 0.2 - 0.085 = 0.115 along x (1.4 and 1.8), 0.1 - 0.025 = 0.075 along y (0.2): 0.075;
    # right: 0.15 - 0.085 = 0.065 along x (1.4), 0.2 - 0.025 along y: 0.065
    assert d["edge_distance_min"] == pytest.approx(0.065)
    assert d["edge_distance_median"] == pytest.approx(0.07)


def test_a_terrain_whose_steps_are_all_below_the_least_step_has_no_edge_distance():
    """A 1 cm step is no step edge (EDGE_MIN_STEP, 2 cm): no edge distance, never an infinite one."""
    from gaitshift.models.terrain import Piece, Terrain
    from gaitshift.sim.perception_metrics import edge_distances

    low = Terrain((Piece(1.0, 3.0, 0.01, 0.01),))
    at = np.ones((1, 2), bool)
    assert edge_distances(at, np.array([[[0.5, 0.1], [0.5, -0.1]]]), low, (0.17, 0.05)) == {}
