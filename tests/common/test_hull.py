"""Convex hulls in the plane (gaitshift.common.hull), against closed forms: the hull of a square with
an inner point is the square, counter-clockwise; the hull margin is the distance to the nearest edge
inside the polygon and minus the distance outside a face, for one point or a batch of points."""

from __future__ import annotations

import numpy as np
import pytest

from gaitshift.common.hull import convex_hull_xy, hull_margin, hull_margins


def test_the_hull_of_a_square_with_an_inner_point_is_the_square_counter_clockwise():
    hull = convex_hull_xy(np.array([[1.0, 1, 0], [-1, 1, 0], [0, 0, 0], [1, -1, 0], [-1, -1, 0], [1, 1, 0]]))
    assert len(hull) == 4
    x, y = hull[:, 0], hull[:, 1]
    assert 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) == pytest.approx(4.0)  # positive: ccw


def test_the_hull_margin_is_the_distance_to_the_nearest_edge_inside_and_negative_outside():
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]])  # an inner point too
    assert hull_margin(square, np.array([0.5, 0.2])) == pytest.approx(0.2)
    assert hull_margin(square, np.array([0.5, 0.5])) == pytest.approx(0.5)
    assert hull_margin(square, np.array([1.3, 0.5])) == pytest.approx(-0.3)
    toe_and_sole = np.array([[0.0, 0.1], [0.0, 0.2], [0.3, -0.2], [0.3, -0.1], [0.5, -0.2], [0.5, -0.1]])
    assert hull_margin(toe_and_sole, np.array([0.2, 0.0])) > 0  # between the toe edge and the other sole
    assert hull_margin(toe_and_sole, np.array([-0.05, 0.15])) < 0  # behind the toe edge: the lifted heel


def test_the_hull_margins_of_a_batch_are_the_distances_to_the_nearest_edges():
    """A batch against the unit square: inside, on the centre, past a face, past a corner (both faces)."""
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    ps = np.array([[0.5, 0.2], [0.5, 0.5], [1.3, 0.5], [-0.1, -0.2], [0.9, 0.7]])
    np.testing.assert_allclose(hull_margins(square, ps), [0.2, 0.5, -0.3, -0.2, 0.1], atol=1e-15)
