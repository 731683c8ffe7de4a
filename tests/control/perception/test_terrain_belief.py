"""The terrain believed from the map: the treads and ramps of a true profile come back as pieces, their
edges within a cell of the truth and their heights within the map's noise; unseen ground is filled only
where the feet stood; noisy far cells do not make ground."""

from __future__ import annotations

import numpy as np
import pytest

from gaitshift.control.perception import ElevationMap, MapSettings
from gaitshift.control.perception.terrain_belief import BeliefSettings, terrain_belief
from gaitshift.models.terrain import Piece, Terrain

R = 0.04
STAIRS = Terrain((Piece(1.0, 1.25, 0.1, 0.1), Piece(1.25, 1.5, 0.2, 0.2), Piece(1.5, 3.0, 0.3, 0.3)))
RAMP = Terrain((Piece(0.6, 1.6, 0.0, 1.0 * np.tan(np.radians(10.0))), Piece(1.6, 3.0, 0.176, 0.176)))


def _seen(truth: Terrain, x_from: float, sigma: float, seed: int = 0, var: float = 1e-5) -> ElevationMap:
    """A map that saw ``truth`` from ``x_from`` on: 4 points per cell with height noise ``sigma`` m."""
    m = ElevationMap(MapSettings(size=4.0, resolution=R))
    m.recenter(np.array([1.0, 0.0]))
    rng = np.random.default_rng(seed)
    xy = m.centres().reshape(-1, 2)
    xy = xy[xy[:, 0] >= x_from]
    pts = np.repeat(xy, 4, axis=0) + rng.uniform(-R / 2, R / 2, (4 * len(xy), 2))
    z = truth.height(pts[:, 0]) + rng.normal(0.0, sigma, len(pts))
    m.fuse(np.column_stack([pts, z]), np.full(len(pts), var))
    return m


def test_stairs_come_back_as_treads_with_edges_within_a_cell_and_heights_within_the_noise():
    m = _seen(STAIRS, 0.4, 0.003)
    b = terrain_belief(m, -0.2, 0.2)
    assert b is not None
    b = b.terrain
    breaks = b.breaks()
    for edge in (1.0, 1.25, 1.5):
        assert np.min(np.abs(breaks - edge)) <= R  # each riser found within one cell
    for x, z in ((0.6, 0.0), (1.125, 0.1), (1.375, 0.2), (2.0, 0.3)):
        assert float(b.height(x)) == pytest.approx(z, abs=0.003)
        assert float(b.slope(x)) == 0.0  # treads are flat, not short ramps


def test_going_down_the_edge_is_where_the_upper_tread_ends_though_its_riser_is_hidden():
    down = Terrain((Piece(-2.0, 1.0, 0.3, 0.3), Piece(1.0, 1.25, 0.2, 0.2), Piece(1.25, 1.5, 0.1, 0.1)))
    m = _seen(down, 0.4, 0.002)
    m.variance[(m.centres()[..., 0] > 1.0) & (m.centres()[..., 0] < 1.1)] = np.inf  # in the upper tread's shadow
    b = terrain_belief(m, -0.2, 0.2)
    assert b is not None
    assert np.min(np.abs(b.terrain.breaks() - 1.0)) <= 1e-9  # not in the middle of the shadow


def test_a_ten_degree_ramp_is_a_ramp_and_its_foot_a_break():
    m = _seen(RAMP, 0.2, 0.002)
    b = terrain_belief(m, -0.2, 0.2)
    assert b is not None
    b = b.terrain
    assert float(b.slope(1.1)) == pytest.approx(np.tan(np.radians(10.0)), rel=0.05)
    assert float(b.slope(0.4)) == 0.0 and float(b.height(0.4)) == pytest.approx(0.0, abs=0.003)
    assert np.min(np.abs(b.breaks() - 0.6)) <= 2 * R


def test_unseen_ground_is_filled_only_where_the_feet_stood():
    m = _seen(STAIRS, 1.1, 0.002)
    belief = terrain_belief(m, -0.2, 0.2, stood=[(-0.085, 0.085, 0.0)])
    assert belief is not None
    b, seen = belief.terrain, belief.seen
    assert float(b.height(0.0)) == pytest.approx(0.0, abs=1e-9)  # where it stood
    assert float(b.height(1.375)) == pytest.approx(0.2, abs=0.003)
    assert seen == pytest.approx((-0.08, 2.98), abs=0.041)  # from the stood sole's cells to the map's end
    # between them nothing was seen: the break lies where the higher ground's seen cells start
    gap = b.breaks()[(b.breaks() > 0.085) & (b.breaks() < 1.2)]
    first = m.centres()[..., 0][m.known].min() - R / 2  # the first seen cell's near side
    assert len(gap) == 1 and gap[0] == pytest.approx(first, abs=1e-9)
    assert terrain_belief(ElevationMap(MapSettings(size=4.0, resolution=R)), -0.2, 0.2) is None


def test_cells_noisier_than_max_std_make_no_ground():
    m = _seen(STAIRS, 0.4, 0.003, var=0.03**2)  # every cell seen, but each to 3 cm / 2
    assert terrain_belief(m, -0.2, 0.2, BeliefSettings(max_std=0.01)) is None
    assert terrain_belief(m, -0.2, 0.2, BeliefSettings(max_std=0.02)) is not None
