"""What the planner is told of a scenario's terrain (``--terrain``, ``sim: {terrain}``): ``blind`` plans
every foothold at the height the robot starts on while the scenario (so the world) keeps its stairs;
``known`` plans them on the treads; a live-command scenario on terrain runs blind (its generator plans
on flat ground) and says so when asked for ``known``; an unknown value is one line naming the field."""

from __future__ import annotations

import numpy as np
import pytest

from gaitshift.control.drivers import prepare
from gaitshift.errors import InputError
from gaitshift.scenario import load_scenario
from gaitshift.scenario.terrain import terrain_of

LOCOMOTION_ON_A_STEP = {
    "planner": "locomotion",
    "robot": "g1",
    "gait": "walk",
    "commands": [{"vx": 0.3}],
    "stop_at": 1.0,
    "terrain": [{"x": [1.0, 3.0], "z": [0.05, 0.05]}],
}


def test_a_blind_planner_plans_on_the_floor_while_the_world_keeps_the_stairs():
    sc, _, _, known = prepare("g1-stairs-up")
    sc_blind, _, _, blind = prepare("g1-stairs-up", terrain="blind")
    ground = terrain_of(sc_blind.terrain)
    assert not ground.flat and sc_blind.terrain == sc.terrain  # the world's ground
    on_stairs = ground.height(known.footsteps[:, 0]) > 0
    assert on_stairs.any()
    np.testing.assert_allclose(known.footsteps[:, 2], ground.height(known.footsteps[:, 0]), atol=1e-9)
    assert np.all(blind.footsteps[:, 2] == 0.0) and blind.meta.get("terrain") in (None, [])
    down, _, _, blind_down = prepare("g1-stairs-down", terrain="blind")  # it starts on the 0.3 m landing
    start = terrain_of(down.terrain).height(0.0)
    assert start == pytest.approx(0.3) and np.allclose(blind_down.footsteps[:, 2], start)


def test_a_live_command_scenario_on_terrain_runs_blind_and_refuses_known():
    sc = load_scenario(LOCOMOTION_ON_A_STEP)
    with pytest.raises(InputError) as info:
        prepare(sc)
    assert info.value.field == "sim.terrain" and "blind" in info.value.allowed
    sc_blind, _, driver, _ = prepare(sc, terrain="blind")
    assert driver is not None and sc_blind.terrain == sc.terrain
    in_block = load_scenario(LOCOMOTION_ON_A_STEP | {"sim": {"terrain": "blind"}})
    assert prepare(in_block)[2] is not None


@pytest.mark.parametrize("bad", ["told", "x", "Perceived"])
def test_an_unknown_terrain_knowledge_is_one_line_naming_the_flag(bad):
    with pytest.raises(InputError) as info:
        prepare("g1-stairs-up", terrain=bad)
    assert info.value.field == "--terrain" and "known, blind, perceived" in info.value.allowed


def test_perceived_on_a_live_command_scenario_is_one_line_naming_the_flag():
    with pytest.raises(InputError) as info:
        prepare(load_scenario(LOCOMOTION_ON_A_STEP), terrain="perceived")
    assert info.value.field == "--terrain" and "tvlip only" in info.value.allowed


BLOCKS = "docs/perception/g1-blocks-walk.yaml"


def test_a_field_of_blocks_is_never_told_to_the_planner():
    """Blocks are a 2-D ground; the planner's terrain is a profile z(x): ``known`` is one line naming the
    field, and perceived plans blind while the world keeps the blocks."""
    from pathlib import Path

    path = Path(__file__).parents[2] / BLOCKS
    with pytest.raises(InputError) as info:
        prepare(str(path), terrain="known")
    assert info.value.field == "--terrain" and "blocks" in info.value.allowed
    sc, _, driver, traj = prepare(str(path))  # its sim: {terrain: perceived}
    assert driver is not None and getattr(driver, "perceives", False)
    assert np.all(traj.footsteps[:, 2] == 0.0)  # blind at the start
    assert terrain_of(sc.terrain).blocks  # the world's ground holds them


@pytest.mark.parametrize(
    ("piece", "says"),
    [
        ({"x": [1.0, 2.0], "z": [0.0, 0.1], "blocks": {"size": 0.3, "height": 0.0, "seed": 0}}, "flat piece"),
        ({"x": [1.0, 2.0], "z": [0.03, 0.03], "blocks": {"size": 0.3, "height": 0.04, "seed": 0}}, "below the floor"),
        ({"x": [1.0, 2.0], "z": [0.04, 0.04], "blocks": {"size": 0.01, "height": 0.04, "seed": 0}}, "size"),
        ({"x": [1.0, 2.0], "z": [0.04, 0.04], "blocks": {"size": 0.3, "height": 0.04, "seed": -1}}, "seed"),
    ],
    ids=["on-a-ramp", "below-the-floor", "too-small", "negative-seed"],
)
def test_a_bad_field_of_blocks_is_one_line_naming_it(piece, says):
    from gaitshift.scenario import load_scenario as load

    bad = {"planner": "tvlip", "robot": "g1", "gait": [{"gait": "walk", "steps": 4}], "terrain": [piece]}
    with pytest.raises(InputError) as info:
        load(bad)
    assert "terrain" in info.value.field and says in str(info.value)
    assert "\n" not in str(info.value)
