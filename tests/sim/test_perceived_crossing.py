"""The G1 climbs three 10 cm stairs (docs/perception/g1-stairs-up-ahead.yaml) and walks a field of
random blocks (g1-blocks-walk.yaml) it is not told about, on its estimated state, from its
camera's map; told nothing and seeing nothing (blind) it falls on both, so the crossing is the map's
doing. The world's truth judges: the pelvis ends past the terrain, and every touchdown's true sole lies
on the ground under it, clear of the true edges."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gaitshift.scenario.terrain import terrain_of
from gaitshift.sim.perception_metrics import stances
from gaitshift.sim.scenario_run import simulate_scenario

SCENARIO = Path(__file__).resolve().parents[2] / "docs" / "perception" / "g1-stairs-up-ahead.yaml"


@pytest.fixture(scope="module")
def perceived():
    return simulate_scenario(str(SCENARIO), seed=0)  # the scenario says sim: {terrain: perceived}


def test_the_g1_climbs_stairs_it_only_sees(perceived):
    r = perceived.result
    assert not r.fell, r.metrics.get("fall_reason")
    truth = terrain_of(perceived.scenario.terrain)
    x_end = float(r.arrays["qpos"][-1, 0])
    assert x_end > 1.5 + 0.2  # on the landing, past the last edge
    at = stances(r.arrays["contact"].astype(bool), float(r.meta["control_period"]))
    feet = r.arrays["foot_pos"]
    ground = truth.height(feet[:, :, 0])
    assert np.abs(feet[at][:, 2] - ground[at]).max() < 0.02  # each sole stands on the tread under it
    p = r.metrics["perception"]
    assert p["edge_distance_min"] > -0.02  # no sole lands more than 2 cm over an edge
    assert perceived.driver.replans >= 3 and perceived.driver.stopped is None


def test_blind_on_the_same_stairs_falls():
    run = simulate_scenario(str(SCENARIO), seed=0, terrain="blind")
    assert run.result.fell


BLOCKS = SCENARIO.parent / "g1-blocks-walk.yaml"


def test_the_g1_walks_a_field_of_blocks_it_only_sees_each_sole_on_one_block():
    """docs/perception/g1-blocks-walk.yaml (0.45 m blocks +-4 cm, footholds judged in the plane),
    seed 0: no fall, past the field's end; every stance's true sole stands on the true ground under it
    and keeps clear of every block side that is a step."""
    run = simulate_scenario(str(BLOCKS), seed=0)
    r = run.result
    assert not r.fell, r.metrics.get("fall_reason")
    assert float(r.arrays["qpos"][-1, 0]) > 3.7  # past the field
    truth = terrain_of(run.scenario.terrain)
    at = stances(r.arrays["contact"].astype(bool), float(r.meta["control_period"]))
    feet = r.arrays["foot_pos"][at]
    assert np.abs(feet[:, 2] - truth.height_xy(feet[:, 0], feet[:, 1])).max() < 0.02  # flat on its block
    assert r.metrics["perception"]["edge_distance_min"] > 0.0  # no sole across a step


def test_blind_on_the_same_blocks_falls():
    assert simulate_scenario(str(BLOCKS), seed=0, terrain="blind").result.fell
