"""Footholds on the 2-D map (eq. (1) of control/perception/patches.py): a sole across a block's side
moves to the nearest level, seen patch, along x or y, with the margin from every side; its height is
its own block's, not the other foot's; a flat place stays as planned, and so does one whose cells are
too unsure to show a step, and one on a ramp the profile believes in; nothing level within reach is None."""

from __future__ import annotations

import numpy as np
import pytest

from gaitshift.control.perception.elevation_map import ElevationMap
from gaitshift.control.perception.patches import PatchRules, level_patch
from gaitshift.models.blocks import Blocks
from gaitshift.models.terrain import Piece, Terrain
from map_checks import seen_map

RULES = PatchRules(length=0.17, width=0.05, margin=0.03)


def _mapped(terrain: Terrain, seen: float = 1e-6) -> ElevationMap:
    """A map of 2 cm cells that saw ``terrain`` exactly (variance ``seen`` m^2)."""
    return seen_map(terrain, 1.5, resolution=0.02, variance=seen)


BLOCKS = Terrain((Piece(1.0, 2.6, 0.04, 0.04, Blocks(0.4, 0.04, 1, half_width=0.8)),))  # sides at x 1.4 1.8 2.2


def _flat_under(t: Terrain, p, length=0.17 + 0.06, width=0.05 + 0.06) -> float:
    xs, ys = np.meshgrid(np.linspace(-0.5, 0.5, 9) * length + p.x, np.linspace(-0.5, 0.5, 5) * width + p.y)
    return float(np.ptp(t.height_xy(xs, ys)))


def _high_side() -> float:
    """The x of a block side on the row y = 0.2 where the tops differ by more than 3 cm."""
    off = BLOCKS.blocks[0].blocks.offsets(1.0, 2.6)[:, 2]  # the row 0 <= y < 0.4
    i = int(np.flatnonzero(np.abs(np.diff(off)) > 0.03)[0])
    return 1.0 + 0.4 * (i + 1)


def test_a_sole_across_a_block_side_moves_to_the_nearest_level_patch_keeping_the_margin():
    emap = _mapped(BLOCKS)
    side = _high_side()
    p = level_patch(emap, side + 0.02, 0.2, 0.0, RULES)  # the heel on the block before the side
    assert p is not None and p.moved and p.x != side + 0.02
    assert _flat_under(BLOCKS, p) <= RULES.flat_tol  # the sole and its margin on ground flat to tau
    assert BLOCKS.edge_distance(p.x, p.y, 0.085, 0.025) >= RULES.margin - 0.02  # within a cell of the margin
    assert abs(p.x - 1.42) <= RULES.reach[0] and abs(p.y - 0.2) <= RULES.reach[1]
    assert p.z == pytest.approx(float(BLOCKS.height_xy(p.x, p.y)), abs=1e-9)  # its own block's height
    assert p.room[0] <= p.x <= p.room[1] and p.room[2] <= p.y <= p.room[3]


def test_a_flat_place_stays_as_planned_at_its_own_blocks_height():
    emap = _mapped(BLOCKS)
    for y in (-0.2, 0.2):  # the two feet's blocks, each side of the line y = 0
        p = level_patch(emap, 1.6, y, 0.0, RULES)
        assert p is not None and (p.x, p.y) == (1.6, y) and not p.moved
        assert p.z == pytest.approx(float(BLOCKS.height_xy(1.6, y)), abs=1e-9)
    assert level_patch(emap, 1.6, 0.2, 0.0, RULES).z != level_patch(emap, 1.6, -0.2, 0.0, RULES).z


def test_the_room_is_where_the_centre_stays_flat():
    emap = _mapped(BLOCKS)
    p = level_patch(emap, 1.6, 0.2, 0.0, RULES)
    for x in np.linspace(p.room[0], p.room[1], 5):
        for y in np.linspace(p.room[2], p.room[3], 5):
            assert _flat_under(BLOCKS, type(p)(x, y, 0.0, False, p.room), 0.17 + 0.02, 0.05 + 0.02) <= RULES.flat_tol


def test_nothing_flat_within_reach_and_unseen_ground_give_none():
    rough = Terrain(
        (Piece(1.0, 2.6, 0.04, 0.04, Blocks(0.06, 0.04, 1, half_width=0.8)),)
    )  # blocks smaller than the sole
    assert level_patch(_mapped(rough), 1.6, 0.2, 0.0, RULES) is None
    assert level_patch(ElevationMap(), 1.6, 0.2, 0.0, RULES) is None  # nothing seen


def test_on_a_ramp_the_profile_believes_in_the_patch_is_level_along_its_slope():
    ramp = Terrain((Piece(1.0, 3.0, 0.0, 0.35),))  # 10 degrees
    p = level_patch(_mapped(ramp), 1.8, 0.1, 0.0, RULES, slope=float(ramp.slope(1.8)))
    assert p is not None and not p.moved and p.z == pytest.approx(float(ramp.height(1.8)), abs=2e-3)
    assert level_patch(_mapped(ramp), 1.8, 0.1, 0.0, RULES) is None  # told flat: nothing level within reach


def test_a_foothold_is_not_moved_on_noise_alone():
    noisy = _mapped(BLOCKS, seen=0.05**2)  # cells known to 5 cm only: no step can be told apart
    p = level_patch(noisy, _high_side() + 0.02, 0.2, 0.0, RULES)
    assert p is not None and (p.x, p.y) == (_high_side() + 0.02, 0.2)
