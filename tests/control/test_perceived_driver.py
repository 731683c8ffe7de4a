"""The perceived-terrain driver moves the footholds it has not committed onto the map it is handed, and
only onto that: the treads' heights, the soles clear of the edges by the margin, the plan continuous
at every re-plan, the committed footholds and the past untouched. The world's terrain never reaches
it (the scenario it plans is flat), so a map of flat ground leaves the blind plan as it was."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

import gaitshift
from gaitshift.control.controller import Controller
from gaitshift.control.drivers import prepare
from gaitshift.control.perceived_driver import PerceivedDriver
from gaitshift.control.perception import ElevationMap, MapSettings
from gaitshift.errors import InputError
from gaitshift.models.terrain import Piece, Terrain
from gaitshift.planners.tvlip.resolve import lift_phase
from gaitshift.scenario.terrain import terrain_of

BUILTIN = Path(gaitshift.__file__).parent / "scenario" / "builtin"


def _scenario() -> dict:
    """g1-stairs-up with its three 10 cm stairs 0.75 m further on (the camera sees them coming)."""
    sc = yaml.safe_load((BUILTIN / "g1-stairs-up.yaml").read_text())
    sc["gait"] = [{"gait": "walk", "steps": 10}]
    sc["terrain"] = [
        {"x": [1.0, 1.25], "z": [0.1, 0.1]},
        {"x": [1.25, 1.5], "z": [0.2, 0.2]},
        {"x": [1.5, 4.0], "z": [0.3, 0.3]},
    ]
    return sc


def _map_of(truth: Terrain) -> ElevationMap:
    m = ElevationMap(MapSettings(size=4.0, resolution=0.04))
    m.recenter(np.array([1.0, 0.0]))
    xy = m.centres().reshape(-1, 2)
    m.fuse(np.column_stack([xy, truth.height(xy[:, 0])]), np.full(len(xy), 1e-6))
    return m


def _drive(driver: PerceivedDriver) -> list[tuple[float, object, object]]:
    """Every tick of the plan through the driver; (t, plan before, plan after) at each re-plan."""
    out = []
    for t in np.arange(0.0, driver.duration_bound, 0.002):
        before = driver.trajectory
        new = driver.maybe_replan(float(t), np.zeros(3), np.zeros(3))
        if new is not None:
            out.append((float(t), before, new))
    return out


def test_the_planned_scenario_is_flat_and_a_flat_map_changes_nothing():
    sc, _, driver, plan = prepare(_scenario(), None, 0.002, "perceived")
    assert isinstance(driver, PerceivedDriver)
    assert terrain_of(driver.sc.terrain).flat and not terrain_of(sc.terrain).flat  # the world keeps it
    assert np.all(plan.footsteps[:, 2] == 0.0)
    driver.see(_map_of(Terrain()))
    assert _drive(driver) == [] and driver.replans == 0


def test_footholds_move_onto_the_treads_clear_of_the_edges_and_the_plan_stays_continuous():
    sc, _, driver, _ = prepare(_scenario(), None, 0.002, "perceived")
    truth = terrain_of(sc.terrain)
    driver.see(_map_of(truth))
    blind = driver.trajectory
    changes = _drive(driver)
    assert driver.replans == len(changes) >= 1 and driver.refused == 0
    for t, old, new in changes:
        i = round(t / new.dt)
        for name in ("com_pos", "com_vel", "foot_pos"):
            np.testing.assert_allclose(getattr(new, name)[: i + 1], getattr(old, name)[: i + 1], atol=1e-9)
    fs = driver.trajectory.footsteps
    length = sc.foot.size[0]
    np.testing.assert_allclose(fs[:, 2], truth.height(fs[:, 0]), atol=0.005)  # on the treads
    edges = truth.breaks()
    gap = np.min(np.abs(fs[:, :1] - edges[None, :]), axis=1) - length / 2
    assert gap.min() >= driver.settings.edge_margin * length - 0.04  # the margin, less one map cell
    assert fs[-1, 2] == pytest.approx(0.3, abs=0.005) and blind.footsteps[-1, 2] == 0.0
    lift = lift_phase(driver.seq)
    assert (lift[:2] == -1).all()


def test_a_wall_too_high_to_step_on_stops_the_walk_before_it_and_says_so():
    sc, _, driver, _ = prepare(_scenario(), None, 0.002, "perceived")
    wall = Terrain((Piece(1.0, 4.0, 0.4, 0.4),))  # 0.4 m up: beyond limits.max_step_height (0.25 m)
    driver.see(_map_of(wall))
    _drive(driver)
    fs = driver.trajectory.footsteps
    assert driver.stopped is not None and driver.stopped.startswith("stopped at x = ")
    assert fs[:, 0].max() + sc.foot.size[0] / 2 <= 1.0  # no sole reaches the wall
    assert np.all(fs[:, 2] == 0.0)
    np.testing.assert_allclose(fs[-1, 0], fs[-2, 0])  # it ends standing, feet side by side


def test_perceived_is_refused_in_one_line_where_it_cannot_work():
    with pytest.raises(InputError, match="tvlip only"):
        prepare("g1-online-variable-speed", None, 0.002, "perceived")
    with pytest.raises(InputError, match="inline"):
        Controller.from_scenario(_scenario() | {"sim": {"terrain": "perceived"}}, replan="thread")
