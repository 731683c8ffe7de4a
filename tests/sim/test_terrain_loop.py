"""Terrain in the simulator (issue 13): the scene holds the plan's terrain at its heights, and the G1
walks the built-in stairs and ramps up and down closed loop on the estimated state, its stance soles on
the ground (on the tread, not on an edge) and, on a ramp, pitched with it; it runs over the 5 cm step
on the truth and on the estimate, its soles above the edge and its heels on the step."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from gaitshift.api import plan
from gaitshift.models.terrain import Terrain
from gaitshift.robots import load_robot
from gaitshift.scenario import load_scenario
from gaitshift.scenario.terrain import terrain_of
from gaitshift.sim.contacts import ContactSensor
from gaitshift.sim.loop import SimOptions, simulate
from gaitshift.sim.plant import build_plant


def test_the_scene_holds_the_terrain_at_its_heights():
    terrain = Terrain.from_list([[0.25, 0.5, 0.1, 0.1], [0.5, 1.5, 0.1, 0.276], [1.5, 2.0, 0.3, 0.3]])
    plant = build_plant(0.002, "g1", terrain)
    m, d = plant.model, mujoco.MjData(plant.model)
    mujoco.mj_forward(m, d)
    xs = np.array([0.1, 0.3, 0.45, 0.7, 1.0, 1.4, 1.75, 2.5])
    hit = np.zeros(len(xs))
    gid = np.zeros(1, np.int32)
    for i, x in enumerate(xs):
        y = 3.0  # beside the robot
        dist = mujoco.mj_ray(m, d, np.array([x, y, 2.0]), np.array([0.0, 0.0, -1.0]), None, 1, -1, gid)
        hit[i] = 2.0 - dist
        assert gid[0] in plant.ground_geoms
    assert np.allclose(hit, terrain.height(xs), atol=1e-9)
    assert len(plant.ground_geoms) == 4 and len(ContactSensor(plant).ground) == 4


def test_the_scene_holds_a_field_of_blocks_at_the_heights_of_eq_1():
    from gaitshift.models.blocks import Blocks
    from gaitshift.models.terrain import Piece

    blocks = Blocks(0.3, 0.04, 7, half_width=0.6)
    terrain = Terrain((Piece(1.0, 2.15, 0.04, 0.04, blocks),))  # 4 x 4 blocks, the last column 0.25 m
    plant = build_plant(0.002, "g1", terrain)
    m, d = plant.model, mujoco.MjData(plant.model)
    mujoco.mj_forward(m, d)
    rng = np.random.default_rng(0)
    xs, ys = rng.uniform(0.8, 2.4, 300), rng.uniform(-0.9, 0.9, 300)  # ahead of the robot, across the field
    gid, down = np.zeros(1, np.int32), np.array([0.0, 0.0, -1.0])
    hit = np.array(
        [2.0 - mujoco.mj_ray(m, d, np.array([x, y, 2.0]), down, None, 1, -1, gid) for x, y in np.column_stack([xs, ys])]
    )
    off = blocks.offsets(1.0, 2.15)
    assert off.shape == (4, 4) and np.all(np.abs(off) <= 0.04) and np.ptp(off) > 0.04
    assert np.allclose(hit, terrain.height_xy(xs, ys), atol=1e-9)  # the blocks, and the piece's top beside them
    assert np.array_equal(Blocks(0.3, 0.04, 7).offsets(1.0, 2.15), Blocks(0.3, 0.04, 7).offsets(1.0, 2.15))
    assert not np.allclose(Blocks(0.3, 0.04, 8).offsets(1.0, 2.15), Blocks(0.3, 0.04, 7).offsets(1.0, 2.15))


@pytest.mark.parametrize("name", ["g1-stairs-up", "g1-stairs-down", "g1-slope-up", "g1-slope-down"])
def test_g1_walks_the_terrain_on_the_estimated_state_with_its_soles_on_the_ground(name):
    sc = load_scenario(name)
    traj = plan(sc)
    result = simulate(traj)  # the default: sensors, estimator, the controller never sees the truth
    m = result.metrics
    assert not result.fell, result.fall_reason
    assert m["steps_completed"] == m["steps_planned"]
    a = result.arrays
    ground = terrain_of(sc.terrain)
    feet, standing = a["foot_pos"], a["contact"] & a["stance"]  # touching, and a stance for the controller
    for s in (0, 1):
        on = standing[:, s]
        # 2 cm: a sole tilting as it lands; on the wrong tread or an edge it is off by the 10 cm rise
        assert np.max(np.abs(feet[on, s, 2] - ground.height(feet[on, s, 0]))) < 0.02
    assert np.ptp(feet[..., 2]) > 0.25  # the run did go up or down the terrain
    late = standing & (a["t"] > 1.0)[:, None]  # stances after the first steps (the start stands on flat ground)
    tilt = _sole_pitch(result, late)
    slope = np.arctan(ground.slope(feet[..., 0]))[late]
    assert np.percentile(np.abs(tilt - slope), 90) < np.radians(2.0)


def _sole_pitch(result, mask):
    """Pitch (rad, toe up) of the soles where ``mask`` (n, 2) holds, from the logged joint angles."""
    plant = build_plant(0.002, "g1", Terrain.from_list(result.meta["plan_meta"]["terrain"]))
    m, d = plant.model, mujoco.MjData(plant.model)
    out = []
    for k, s in zip(*np.nonzero(mask), strict=True):
        d.qpos[:] = result.arrays["qpos"][k]
        mujoco.mj_kinematics(m, d)
        R = plant.sole_frame(d, int(s))[1]
        out.append(np.arctan2(R[2, 0], np.hypot(R[0, 0], R[1, 0])))
    return np.array(out)


@pytest.mark.parametrize("state", ["oracle", "estimated"])
def test_g1_runs_over_the_5cm_step_with_its_soles_above_the_edge_and_its_heels_on_the_step(state):
    """On the estimate the touchdown is kept 2 std of the position estimate from the edge: without that
    margin the heel landed 3 cm short, on the edge, and the run fell (docs/simulation.md, "Terrain")."""
    sc = load_scenario("g1-run-step")
    result = simulate(plan(sc), SimOptions(state=state))
    assert not result.fell, result.fall_reason
    assert result.metrics["steps_completed"] == result.metrics["steps_planned"]
    a = result.arrays
    (edge,) = terrain_of(sc.terrain).breaks()[:1]
    over = ~a["contact"] & (np.abs(a["foot_pos"][..., 0] - edge) < sc.foot.size[0] / 2)
    assert over.any() and np.min(a["foot_pos"][..., 2][over]) > 0.05 + 0.01  # 1 cm above the 5 cm step
    # every sole that stands on the step has its heel on it (true positions; 5 mm: the heel's rounded
    # collision sphere; the oracle's lands 2.4 mm over, the estimate's fell 3.2 cm over)
    up = a["contact"] & (a["foot_pos"][..., 2] > 0.025)
    half = load_robot("g1").sole_size[0] / 2
    assert up.any() and np.min(a["foot_pos"][..., 0][up]) - half > edge - 0.005
