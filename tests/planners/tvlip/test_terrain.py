"""TV-LIPM plans over terrain (issue 13): footholds on the ground, the 3D ZMP identity with the
foothold heights, a CoM height that follows the terrain, and swings that clear the stair edges."""

from __future__ import annotations

import numpy as np
import pytest

from gaitshift.api import plan
from gaitshift.errors import InputError, ScenarioError
from gaitshift.gait.swing import EdgeClearance, swing_path
from gaitshift.models.terrain import Piece, Terrain
from gaitshift.scenario import load_scenario
from gaitshift.scenario.terrain import terrain_of
from gaitshift.trajectory.contract import FLIGHT

STAIRS = ("g1-stairs-up", "g1-stairs-down")


@pytest.fixture(scope="module", params=STAIRS)
def planned(request):
    sc = load_scenario(request.param)
    return sc, plan(sc)


def test_terrain_height_slope_and_breaks():
    t = Terrain((Piece(0.0, 1.0, 0.0, 0.1), Piece(1.0, 2.0, 0.1, 0.1), Piece(2.5, 3.0, 0.2, 0.2)))
    assert np.allclose(t.height([-1.0, 0.5, 1.5, 2.2, 2.7, 3.5]), [0.0, 0.05, 0.1, 0.0, 0.2, 0.0])
    assert np.allclose(t.slope([0.5, 1.5]), [0.1, 0.0])
    # x = 1: the ramp meets the flat tread (slope changes); 2, 2.5, 3: the height jumps; 0: foot of the ramp
    assert t.breaks().tolist() == [0.0, 1.0, 2.0, 2.5, 3.0]
    assert t.sole_fits(1.5, 0.0, 0.17, 0.05) is None
    assert t.sole_fits(1.95, 0.0, 0.17, 0.05) == 2.0
    with pytest.raises(ValueError, match="overlap"):
        Terrain((Piece(0.0, 1.0, 0.1, 0.1), Piece(0.5, 2.0, 0.1, 0.1)))


def test_a_clamped_sole_keeps_the_margin_from_height_steps_only_and_centres_on_a_short_tread():
    t = Terrain((Piece(0.0, 1.0, 0.0, 0.1), Piece(1.0, 2.0, 0.1, 0.1), Piece(2.0, 2.25, 0.2, 0.2)))
    half = 0.09
    # the tread 1-2 m: a ramp's kink at 1 (no margin), a 10 cm step at 2 (margin)
    assert t.is_step(2.0) and not t.is_step(1.0)
    assert t.clamp_sole(1.5, 0.9, half, 0.05) == pytest.approx(1.0 + half)
    assert t.clamp_sole(1.5, 2.0, half, 0.05) == pytest.approx(2.0 - half - 0.05)
    assert t.clamp_sole(1.5, 2.0, half, 0.0) == pytest.approx(2.0 - half)
    # the 0.25 m tread 2-2.25 has 0.07 m of room for a 0.18 m sole: both margins shrink, the sole centres
    assert t.clamp_sole(2.1, 2.0, half, 0.05) == pytest.approx(2.125)
    assert t.clamp_sole(2.1, 2.3, half, 0.05) == pytest.approx(2.125)
    assert t.clamp_sole(2.1, 2.1, half, 0.01) == pytest.approx(2.1)  # inside the margins: untouched


def test_footholds_and_stance_soles_sit_on_the_terrain(planned):
    sc, traj = planned
    ground = terrain_of(sc.terrain)
    fs = traj.footsteps
    assert np.allclose(fs[:, 2], ground.height(fs[:, 0]), atol=1e-12)
    assert np.ptp(fs[:, 2]) == pytest.approx(0.3)  # three 10 cm stairs
    on = traj.contact
    soles = traj.foot_pos[on]  # every sole in contact
    assert np.allclose(soles[:, 2], ground.height(soles[:, 0]), atol=1e-9)


def test_zmp_identity_in_3d_with_the_foothold_heights(planned):
    """Point mass: p_zmp,xy = c_xy - (c_z - z_zmp) / (c''_z + g) c''_xy, and in single support the ZMP
    height is the stance foothold's."""
    sc, traj = planned
    g = sc.gravity
    sup = traj.phase != FLIGHT
    c, a, p = traj.com_pos[sup], traj.com_acc[sup], traj.zmp[sup]
    rhs = c[:, :2] - ((c[:, 2] - p[:, 2]) / (a[:, 2] + g))[:, None] * a[:, :2]
    assert np.max(np.abs(p[:, :2] - rhs)) < 1e-9
    single = traj.contact.sum(axis=1) == 1
    stance = traj.foot_pos[single][traj.contact[single]]
    assert np.allclose(traj.zmp[single, 2], stance[:, 2], atol=1e-5)  # the z box of eq. (7), solved iteratively
    assert np.ptp(p[:, 2]) == pytest.approx(0.3, abs=1e-4)  # the ZMP climbs / descends with the stairs


def test_com_height_follows_the_terrain(planned):
    sc, traj = planned
    fs = traj.footsteps
    start, end = fs[:2, 2].mean(), fs[-2:, 2].mean()
    assert traj.com_pos[0, 2] == pytest.approx(start + sc.height, abs=1e-8)  # a KKT boundary row: 1.3e-9 on AMD EPYC
    assert traj.com_pos[-1, 2] == pytest.approx(end + sc.height, abs=1e-6)
    sup = traj.phase != FLIGHT
    above = traj.com_pos[sup, 2] - traj.zmp[sup, 2]
    assert np.all(above > 0.8 * sc.height) and np.all(above < 1.35 * sc.height)


def test_swings_clear_every_stair_edge_by_the_edge_clearance(planned):
    sc, traj = planned
    ground = terrain_of(sc.terrain)
    half = sc.foot.size[0] / 2 + sc.edge_clearance  # the sole and the margin beyond toe and heel
    b = ground.breaks()
    top = np.maximum(ground.height(b - 1e-9), ground.height(b)) + sc.edge_clearance  # (nb,)
    checked = 0
    for side in (0, 1):
        swing = ~traj.contact[:, side]
        x, z = traj.foot_pos[swing, side, 0], traj.foot_pos[swing, side, 2]
        over = np.abs(x[:, None] - b[None, :]) < half  # (n, nb): an edge under the sole
        checked += int(over.sum())
        # 0.1 mm: the window is chosen on 1001 samples of the swing, the plan has its own samples
        assert np.min(np.where(over, z[:, None] - top, np.inf)) > -1e-4
    assert checked > 100  # the swings did pass over edges


def test_the_plain_swing_would_hit_the_first_stair_edge():
    """Without the window the sole meets the riser: the window is what clears it."""
    sc = load_scenario("g1-stairs-up")
    ground = terrain_of(sc.terrain)
    start, end = np.array([0.125, 0.0, 0.0]), np.array([0.625, 0.0, 0.2])
    u = np.linspace(0.0, 1.0, 401)
    plain = swing_path(start, end, sc.swing_height, u)
    near = np.abs(plain[:, 0] - 0.25) < sc.foot.size[0] / 2
    assert np.min(plain[near, 2]) < 0.1  # below the 10 cm tread: a collision
    window = EdgeClearance(ground, sc.foot.size[0], sc.edge_clearance).window(start, end, sc.swing_height)
    assert 0.0 < window[0] < 0.5 and window[1] <= 1.0
    shaped = swing_path(start, end, sc.swing_height, u, window)
    near = np.abs(shaped[:, 0] - 0.25) < sc.foot.size[0] / 2
    assert np.min(shaped[near, 2]) >= 0.1 + sc.edge_clearance - 1e-9


def test_a_sole_across_an_edge_or_overlapping_pieces_are_input_errors():
    base = {
        "planner": "tvlip",
        "gait": [{"gait": "walk", "steps": 2}],
        "profile": {"max_stride": 0.25, "accelerate_steps": 0, "decelerate_steps": 0},
    }
    with pytest.raises(InputError, match="terrain"):  # the first foothold's sole spans x 0.14..0.36
        plan(load_scenario({**base, "terrain": [{"x": [0.3, 2.0], "z": [0.1, 0.1]}]}))
    with pytest.raises(ScenarioError, match="terrain"):
        load_scenario({**base, "terrain": [{"x": [0.5, 1.0], "z": [0.1, 0.1]}, {"x": [0.8, 2.0], "z": [0.1, 0.1]}]})
    with pytest.raises(ScenarioError, match="terrain"):
        load_scenario({**base, "terrain": [{"x": [0.5, 1.0], "z": [0.1, -0.1]}]})
