"""The G1 climbs three 10 cm stairs it is not told about, on its estimated state, from its camera's map
(docs/perception/g1-stairs-up-ahead.yaml); told nothing and seeing nothing (blind) it falls there, so
the crossing is the map's doing. The world's truth judges: the pelvis ends on the landing, and every
touchdown's true sole lies on a tread, clear of the true edges."""

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
