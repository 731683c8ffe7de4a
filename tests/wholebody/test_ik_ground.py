"""The ground inequality of the reference IK (gaitshift.wholebody.ik_ground), against closed forms: a
G1 standing 10 mm above a flat floor has each held corner's clearance h = 10 mm and the row G = -dz/dq
(lifting the base lowers no corner: G @ e_z = -1); on a ramp of slope s the row is s dx/dq - dz/dq and h
the corner's height above the ramp; only the heel corners of a pivoting sole, and every corner of a swing
sole whose height is soft or of both soles of a reached flight, are held; a swing sole's centre held on or
above a height z_p has the row -dz/dq of the centre and h = its height - z_p."""

from __future__ import annotations

import mink
import numpy as np
import pytest

from gaitshift.models.terrain import Terrain
from gaitshift.robots import load_robot
from gaitshift.robots.config import RobotConfig
from gaitshift.wholebody.ik_ground import GroundLimit


@pytest.fixture(scope="module")
def standing():
    robot = load_robot("g1")
    model = robot.model()
    conf = mink.Configuration(model, robot.standing_qpos(model))
    sites = [model.site(n).id for n in RobotConfig.SOLE_SITES]
    lowest = conf.data.site_xpos[sites, 2].min()
    q = conf.q.copy()
    q[2] += 0.01 - lowest  # soles 10 mm above z = 0
    conf.update(q)
    return robot, model, conf, sites


def test_flat_ground_rows_are_minus_the_corner_heights_jacobian(standing):
    robot, model, conf, sites = standing
    g = GroundLimit(model, sites, robot.sole_size, Terrain.from_list(None))
    g.hold((False, False), (False, False))
    assert g.compute_qp_inequalities(conf, 1.0).inactive
    g.hold((True, False), (False, False))
    G, h = g.compute_qp_inequalities(conf, 1.0)
    assert G.shape == (2, model.nv)  # the two heel corners of the left sole
    np.testing.assert_allclose(h, 0.01, atol=2e-4)  # the standing soles are flat to 0.2 mm
    np.testing.assert_allclose(G[:, 2], -1.0)  # the base's z moves every corner up one for one
    g.hold((False, False), (True, True))
    assert g.compute_qp_inequalities(conf, 1.0).G.shape == (8, model.nv)


def test_on_a_ramp_the_row_follows_the_slope_and_h_the_height_above_it(standing):
    robot, model, conf, sites = standing
    s = 0.2
    ramp = Terrain.from_list([[-5.0, 5.0, -5.0 * s, 5.0 * s]])
    g = GroundLimit(model, sites, robot.sole_size, ramp)
    g.hold((False, False), (True, True))
    G, h = g.compute_qp_inequalities(conf, 1.0)
    corners = np.vstack([g.corners(conf.data, 0), g.corners(conf.data, 1)])
    np.testing.assert_allclose(h, corners[:, 2] - s * corners[:, 0], atol=1e-12)
    np.testing.assert_allclose(G[:, 0], s, atol=1e-12)  # the base's x: the ground under the corner rises
    np.testing.assert_allclose(G[:, 2], -1.0, atol=1e-12)


def test_a_swing_soles_centre_is_held_above_its_planned_height(standing):
    robot, model, conf, sites = standing
    g = GroundLimit(model, sites, robot.sole_size, Terrain.from_list(None))
    g.hold((False, False), (False, True), (None, 0.004))  # the right sole in the air, its plan 4 mm up
    G, h = g.compute_qp_inequalities(conf, 1.0)
    assert G.shape == (5, model.nv)  # its centre, then its four corners
    centre = conf.data.site_xpos[sites[1], 2]
    np.testing.assert_allclose(h[0], centre - 0.004, atol=1e-12)  # 6 mm above the planned height
    np.testing.assert_allclose(G[0, :3], [0.0, 0.0, -1.0], atol=1e-12)  # only the base's z moves it up
