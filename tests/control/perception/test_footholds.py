"""Footholds on believed ground (eq. (1) of control/perception/footholds.py): the safe place nearest
the planned one keeps the sole on one tread with the margin from a step edge, within the stride and
the rise of the previous foothold and on seen ground; nowhere safe is None."""

from __future__ import annotations

import numpy as np
import pytest

from gaitshift.control.perception.footholds import FootholdRules, place
from gaitshift.models.terrain import Piece, Terrain

RULES = FootholdRules(length=0.17, width=0.05, edge_margin=0.03, max_stride=0.4, max_rise=0.25)
STAIRS = Terrain((Piece(1.0, 1.3, 0.1, 0.1), Piece(1.3, 4.0, 0.2, 0.2)))


def test_a_sole_across_an_edge_moves_the_least_that_keeps_the_margin():
    x = place(STAIRS, 3.0, 1.02, 0.0, (0.8, 0.0), RULES)
    assert x == pytest.approx(1.0 + 0.085 + 0.03)  # onto the tread, the margin behind the heel
    x = place(STAIRS, 3.0, 0.95, 0.0, (0.8, 0.0), RULES)
    assert x == pytest.approx(1.0 - 0.085 - 0.03)  # nearer before the edge than after it
    assert place(STAIRS, 3.0, 1.15, 0.0, (0.9, 0.0), RULES) == pytest.approx(1.15)  # safe as planned


def test_a_tread_shorter_than_sole_and_margins_shares_the_room_between_both_edges():
    t = Terrain((Piece(1.0, 1.2, 0.1, 0.1), Piece(1.2, 4.0, 0.2, 0.2)))  # 0.20 m tread: 1.5 cm each side
    x = place(t, 3.0, 1.05, 0.0, (0.9, 0.0), RULES)
    assert x == pytest.approx(1.1)


def test_steps_stay_within_the_stride_of_the_previous_foothold():
    t = Terrain((Piece(0.7, 4.0, 0.1, 0.1),))
    x = place(t, 3.0, 0.75, 0.0, (0.2, 0.0), RULES)  # the tread's start is out of reach of 0.2 + 0.4
    assert x == pytest.approx(0.7 - 0.085 - 0.03) and abs(x - 0.2) <= RULES.max_stride


@pytest.mark.parametrize(
    ("prev", "seen_to"),
    [((0.8, -0.3), 3.0), ((0.9, 0.0), 1.0)],
    ids=["too-high-to-step-on", "planned-place-unseen"],
)
def test_a_blocked_path_is_none(prev, seen_to):
    t = Terrain((Piece(0.7, 4.0, 0.1, 0.1),))
    assert place(t, seen_to, 1.2, 0.0, prev, RULES) is None


def test_a_sole_never_lands_beyond_the_seen_ground():
    t = Terrain((Piece(0.7, 4.0, 0.1, 0.1),))
    x = place(t, 1.3, 1.2, 0.0, (0.9, 0.1), RULES)
    assert x is not None and x + 0.085 <= 1.3 + 1e-12


def test_a_yawed_sole_needs_less_room_along_x():
    x0 = place(STAIRS, 3.0, 1.02, 0.0, (0.8, 0.0), RULES)
    x1 = place(STAIRS, 3.0, 1.02, np.pi / 2, (0.8, 0.0), RULES)
    assert x1 == pytest.approx(1.0 + 0.025 + 0.03) and x1 < x0


def test_no_sole_overlaps_a_gap_where_an_edge_hides_and_its_ends_keep_the_margin():
    t = Terrain((Piece(1.0, 4.0, 0.1, 0.1),))  # believed edge at 1.0, but nothing was seen in [0.96, 1.04]
    gaps = [(0.96, 1.04)]
    x = place(t, 3.0, 1.06, 0.0, (0.9, 0.0), RULES, gaps)
    assert x == pytest.approx(1.04 + 0.085 + 0.03)  # the margin from the gap's far end, not from 1.0
    x = place(t, 3.0, 0.95, 0.0, (0.8, 0.0), RULES, gaps)
    assert x == pytest.approx(0.96 - 0.085 - 0.03)
