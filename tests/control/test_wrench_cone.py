"""The contact wrench cone of a sole against independent oracles.

Oracles: Caron, Pham and Nakamura's closed-form 16 faces of a rectangle (ICRA 2015) for the enumeration
(on their box pyramid ``|f_x|, |f_y| <= mu f_z``); the yaw-moment bound ``mu X f_z`` of a rectangle under
the inscribed pyramid ``|f_x| + |f_y| <= mu f_z`` (derived in its test); for any sole (the G1's
trapezoid, an irregular one), membership by non-negative least squares on point forces at the contact
points, each along its own pyramid's edges (built here from the definition): a wrench satisfies the
faces exactly when point forces in the pyramids exert it; the force metric against the least-norm point
forces of ``numpy.linalg.lstsq``.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import nnls

from gaitshift.control.wrench_cone import cone_faces, min_norm_metric, pyramid_edges
from gaitshift.sim.plant import build_plant

MU = 0.45


def _point_map(points: np.ndarray) -> np.ndarray:
    """(6, 3n): point forces (stacked f_i) -> wrench about the origin [sum f; sum r x f]."""
    G = np.zeros((6, 3 * len(points)))
    for i, r in enumerate(points):
        G[:3, 3 * i : 3 * i + 3] = np.eye(3)
        G[3:, 3 * i : 3 * i + 3] = [[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]]
    return G


#: the box pyramid |f_x|, |f_y| <= mu f_z of Caron et al.'s closed form
BOX = np.array([[1, 1, 1], [1, -1, 1], [-1, 1, 1], [-1, -1, 1]], float) * [MU, MU, 1.0]
#: the pyramid |f_x| + |f_y| <= mu f_z (MuJoCo's condim-3 pyramid), built from its definition
INSCRIBED = np.array([[1, 0, 1], [-1, 0, 1], [0, 1, 1], [0, -1, 1]], float) * [MU, MU, 1.0]


def rectangle_faces(X: float, Y: float, mu: float) -> np.ndarray:
    """Caron et al. (2015)'s 16 face rows (16, 6) of a rectangle's contact wrench cone on the box pyramid,
    in the order (f_x, f_y, f_z, tau_x, tau_y, tau_z), ``C w <= 0``::

        |f_x| <= mu f_z,   |f_y| <= mu f_z,   |tau_x| <= Y f_z,   |tau_y| <= X f_z,
        tau_min = -mu (X + Y) f_z + |Y f_x - mu tau_x| + |X f_y - mu tau_y| <= tau_z,
        tau_z <= tau_max = +mu (X + Y) f_z - |Y f_x + mu tau_x| - |X f_y + mu tau_y|.
    """
    rows = [
        [1, 0, -mu, 0, 0, 0],
        [-1, 0, -mu, 0, 0, 0],
        [0, 1, -mu, 0, 0, 0],
        [0, -1, -mu, 0, 0, 0],
        [0, 0, -Y, 1, 0, 0],
        [0, 0, -Y, -1, 0, 0],
        [0, 0, -X, 0, 1, 0],
        [0, 0, -X, 0, -1, 0],
    ]
    for a in (1.0, -1.0):
        for b in (1.0, -1.0):
            rows.append([a * Y, b * X, -mu * (X + Y), -a * mu, -b * mu, -1.0])
            rows.append([a * Y, b * X, -mu * (X + Y), a * mu, b * mu, 1.0])
    return np.array(rows, float)


def _pyramid_generators(points: np.ndarray) -> np.ndarray:
    """(6, 4n): the wrench of a unit-f_z force along each edge of each point's inscribed pyramid."""
    edges = INSCRIBED
    G = _point_map(points)
    cols = [G[:, 3 * i : 3 * i + 3] @ e for i in range(len(points)) for e in edges]
    return np.array(cols).T


def _soles() -> dict[str, np.ndarray]:
    g1 = build_plant(0.002).soles[0].points
    odd = np.array([[0.09, 0.02, 0.0], [0.05, -0.035, 0.0], [-0.08, -0.03, 0.0], [-0.1, 0.025, 0.0], [0.0, 0.04, 0.0]])
    return {"g1": g1, "irregular": odd}


def test_enumerated_faces_of_a_rectangle_are_carons_closed_form():
    X, Y = 0.085, 0.0275
    corners = np.array([[X, Y, 0.0], [X, -Y, 0.0], [-X, Y, 0.0], [-X, -Y, 0.0]])
    found = cone_faces(corners, BOX)
    closed = rectangle_faces(X, Y, MU)
    closed /= np.linalg.norm(closed, axis=1, keepdims=True)
    assert len(found) == len(closed) == 16
    for row in found:  # the same set of unit rows
        assert np.min(np.max(np.abs(closed - row), axis=1)) < 1e-12
    for row in closed:
        assert np.min(np.max(np.abs(found - row), axis=1)) < 1e-12


def test_pyramid_edges_are_the_inscribed_pyramid_on_coulombs_cone():
    edges = pyramid_edges(MU)
    assert {tuple(e) for e in edges} == {tuple(e) for e in INSCRIBED}
    assert np.linalg.norm(edges[:, :2], axis=1) == pytest.approx(MU * edges[:, 2], rel=1e-15)  # on the cone


def test_largest_yaw_moment_of_a_rectangle_is_mu_x_fz():
    """A unit normal load and a yaw moment alone. At corner (+-X, +-Y) a force f_t adds
    ``X f_y - Y f_x`` (signs by corner); under ``|f_x| + |f_y| <= mu f_z,i`` that is at most
    ``mu max(X, Y) f_z,i``, reached with ``f_y`` alone, and the four corners sum to ``mu X f_z``
    (X > Y). The box pyramid would give Caron's ``mu (X + Y)``."""
    X, Y = 0.085, 0.0275
    corners = np.array([[X, Y, 0.0], [X, -Y, 0.0], [-X, Y, 0.0], [-X, -Y, 0.0]])
    for edges, bound in ((pyramid_edges(MU), MU * X), (BOX, MU * (X + Y))):
        C = cone_faces(corners, edges)
        up = C[:, 5] > 1e-12  # rows that bound tau_z from above: C_fz + C_tz tau <= 0
        assert float(np.min(-C[up, 2] / C[up, 5])) == pytest.approx(bound, rel=1e-12)


@pytest.mark.parametrize("name", ["g1", "irregular"])
def test_a_wrench_meets_the_faces_exactly_when_point_forces_in_the_pyramids_exert_it(name):
    points = _soles()[name]
    C = cone_faces(points, pyramid_edges(MU))
    V = _pyramid_generators(points)
    assert np.max(C @ V) < 1e-12  # every generator inside
    for row in C:  # a face: five independent generators on it
        on = V[:, np.abs(row @ V) < 1e-12]
        assert np.linalg.matrix_rank(on, tol=1e-9) == 5
    rng = np.random.default_rng(0)
    scale = np.array([50.0, 50.0, 300.0, 10.0, 10.0, 5.0])
    inside = outside = 0
    for _ in range(400):
        w = rng.normal(size=6) * scale
        w[2] = abs(w[2])
        _, residual = nnls(V, w)
        violation = float(np.max(C @ w))
        if violation <= -1e-6:
            assert residual < 1e-6 * np.linalg.norm(w)
            inside += 1
        elif violation >= 1e-6:
            assert residual > 1e-9
            outside += 1
    assert inside > 20 and outside > 20  # both sides were sampled


@pytest.mark.parametrize("name", ["g1", "irregular"])
def test_metric_is_the_least_sum_of_squared_point_forces(name):
    points = _soles()[name]
    Q = min_norm_metric(points)
    G = _point_map(points)
    rng = np.random.default_rng(1)
    for _ in range(20):
        w = rng.normal(size=6) * [50.0, 50.0, 300.0, 10.0, 10.0, 5.0]
        f = np.linalg.lstsq(G, w, rcond=None)[0]  # the least-norm forces exerting w
        assert w @ Q @ w == pytest.approx(f @ f, rel=1e-9)
