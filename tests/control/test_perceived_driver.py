"""The perceived-terrain driver moves the footholds it has not committed onto the map it is handed, and
only onto that: the treads' heights, the soles clear of the edges by the margin, the plan continuous
at every re-plan, the committed footholds and the past untouched. The world's terrain never reaches
it (the scenario it plans is flat), so a map of flat ground leaves the blind plan as it was."""

from __future__ import annotations

import copy
import threading
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import yaml

import gaitshift
from gaitshift.control.drivers import prepare
from gaitshift.control.perceived_driver import PerceivedDriver, PerceivedSettings
from gaitshift.control.perception import ElevationMap, MapSettings
from gaitshift.control.replanner import replanner
from gaitshift.errors import InputError
from gaitshift.models.terrain import Piece, Terrain
from gaitshift.planners.tvlip.resolve import lift_phase
from gaitshift.scenario.terrain import terrain_of
from map_checks import seen_map
from replan_checks import assert_same, wait_for

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
    return seen_map(truth, 1.0)


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


BLOCKS = Path(__file__).parents[2] / "docs" / "perception" / "g1-blocks-walk.yaml"


def _map_xy(truth: Terrain) -> ElevationMap:
    """A map that saw ``truth`` in the plane exactly, 5 m wide (the whole field)."""
    return seen_map(truth, 2.0, size=5.0)


@pytest.mark.parametrize("rule", ["plane", "profile"])
def test_on_a_field_of_blocks_footholds_in_the_plane_keep_each_sole_on_one_block(rule):
    """``footholds: plane`` judges each foothold on the map in 2-D: every sole on the field keeps the
    margin from every block side that is a step (less a map cell), stands at its own block's height,
    and its room holds it; ``profile`` alone (the band's median along x) does not."""
    sc, _, driver, _ = prepare(str(BLOCKS))
    driver.settings = replace(driver.settings, footholds=rule)
    truth = terrain_of(sc.terrain)
    driver.see(_map_xy(truth))
    _drive(driver)
    fs = driver.trajectory.footsteps
    length, width = sc.foot.size
    on = (fs[:, 0] > 1.0 + length) & (fs[:, 0] < 3.7 - length)  # on the field, clear of its ends
    gap = truth.edge_distance(fs[on, 0], fs[on, 1], length / 2, width / 2)
    height = np.abs(fs[on, 2] - truth.height_xy(fs[on, 0], fs[on, 1]))
    if rule == "profile":
        assert gap.min() < 0 or height.max() > 0.01  # across a side, or at another block's height
        assert driver.trajectory.meta["foothold_rooms"] == []
        return
    assert gap.min() >= driver.patch.margin - 0.04  # the margin, less one map cell
    assert height.max() <= driver.patch.flat_tol  # its own block's height (two within tau: their median)
    rooms = np.array(driver.trajectory.meta["foothold_rooms"])
    inside = (rooms[:, None, 0] - 1e-9 <= fs[:, 0]) & (fs[:, 0] <= rooms[:, None, 1] + 1e-9)
    inside &= (rooms[:, None, 2] - 1e-9 <= fs[:, 1]) & (fs[:, 1] <= rooms[:, None, 3] + 1e-9)
    assert inside[:, on].any(axis=0).all()  # each sole on the field has the room it stands in


def test_perceived_is_refused_in_one_line_where_it_cannot_work():
    with pytest.raises(InputError, match="tvlip only"):
        prepare("g1-online-variable-speed", None, 0.002, "perceived")
    for lead in (-0.1, 2.0, float("nan")):
        with pytest.raises(InputError, match="replan_lead"):
            PerceivedSettings(replan_lead=lead)


def _with_lead(lead: float) -> PerceivedDriver:
    _, _, driver, _ = prepare(_scenario() | {"sim": {"terrain": "perceived", "replan_lead": lead}}, None, 0.002)
    assert isinstance(driver, PerceivedDriver) and driver.settings.replan_lead == lead
    return driver


def test_a_lead_replans_before_the_boundary_and_changes_nothing_before_it_nor_what_is_planned():
    """With ``replan_lead`` 0.1 s each re-plan comes at the first tick at or after ``t_k - 0.1`` and the new
    plan equals the old one up to ``t_k`` (not only up to the re-plan's tick); on a map that does not change,
    the plans are those of no lead."""
    lead, truth = 0.1, terrain_of(prepare(_scenario(), None, 0.002)[0].terrain)
    early, late = _with_lead(lead), _with_lead(0.0)
    instants = early.map_instants()
    np.testing.assert_allclose(instants + lead, late.map_instants())
    for d in (early, late):
        d.see(_map_of(truth))
    changes, plain = _drive(early), _drive(late)
    assert len(changes) == len(plain) >= 1
    tb = early.seq.boundary_times
    for (t, old, new), (t0, _, _) in zip(changes, plain, strict=True):
        k = int(np.searchsorted(tb, t0 + 1e-9, side="right") - 1)  # the boundary re-planned at
        assert tb[k] - lead - 1e-9 <= t < tb[k] - lead + 0.002 and t < t0
        i = round(tb[k] / new.dt)
        for name in ("com_pos", "com_vel", "foot_pos", "zmp"):
            np.testing.assert_array_equal(getattr(new, name)[:i], getattr(old, name)[:i])
    for name in ("com_pos", "foot_pos", "footsteps"):
        np.testing.assert_array_equal(getattr(early.trajectory, name), getattr(late.trajectory, name))


def _growing_map(truth: Terrain, t: float, emap: ElevationMap) -> None:
    """The map as a walk would grow it: at plan time ``t`` s the ground up to x = 0.4 + 0.4 t m, fused again
    (so the host's map changes every tick, after each copy handed to a worker too)."""
    xy = emap.centres().reshape(-1, 2)
    near = xy[xy[:, 0] <= 0.4 + 0.4 * t]
    emap.fuse(np.column_stack([near, truth.height(near[:, 0])]), np.full(len(near), 1e-4))


class Behind:
    """A driver whose worker thread handles each tick only when the host lets it: the host is then
    :data:`BEHIND` ticks further on, and its map has grown since (forwarding everything else)."""

    def __init__(self, driver):
        self.inner, self.go = driver, threading.Semaphore(0)

    def __getattr__(self, name):
        return getattr(self.inner, name)

    def maybe_replan(self, t, com, com_vel):
        self.go.acquire()
        return self.inner.maybe_replan(t, com, com_vel)


#: ticks a held thread worker lags the host by
BEHIND = 50


def _run_through(rp, truth: Terrain, ticks: np.ndarray, inline_at: list[int] | None) -> tuple[list, list[int]]:
    """Every tick through the re-planner ``rp`` with the host's map growing each tick: its plans and the
    ticks they came at. A background worker is waited for at the ticks the inline plans came at,
    ``inline_at`` (its pipe holds ~1000 requests); a :class:`Behind` one is let go :data:`BEHIND` ticks
    late, and waited for at the end."""
    emap = ElevationMap(MapSettings(size=4.0, resolution=0.04))
    emap.recenter(np.array([1.0, 0.0]))
    rp.watch(emap)
    held = getattr(rp.driver, "local", None)
    held = held if isinstance(held, Behind) else None
    got: list = []
    at: list[int] = []
    for n, t in enumerate(ticks):
        _growing_map(truth, float(t), emap)
        got += rp.step(float(t), np.zeros(3), np.zeros(3))
        if held is not None and n >= BEHIND:
            held.go.release()
        elif held is None and inline_at is not None and n in inline_at:
            got += wait_for(rp, inline_at.index(n) + 1 - len(got))
        at += [n] * (len(got) - len(at))
    if held is not None:
        for _ in range(BEHIND):
            held.go.release()
        got += wait_for(rp, len(inline_at or ()) - len(got))
    return got, at


@pytest.mark.parametrize("mode", ["thread", "process"])
def test_a_background_perceived_replan_reads_the_map_of_its_instant_and_is_the_inline_one(mode):
    """The same ticks and the same growing map through the inline driver and a background worker (lead
    0.1 s): the worker is handed a copy of the map at each of the driver's instants and re-plans on it, so
    its plans are the inline ones bit for bit, however late they come, with the same refusals. The thread
    worker is held 50 ticks behind the host: had it read the host's own map, it would have planned on 50
    ticks more of it."""
    truth = terrain_of(prepare(_scenario(), None, 0.002)[0].terrain)
    start, ticks = _with_lead(0.1), np.arange(0.0, 10.0, 0.002)
    inline = replanner(copy.deepcopy(start), "inline", 0.2)  # the same driver (its plan's meta has a wall time)
    expected, at = _run_through(inline, truth, ticks, None)
    driver = copy.deepcopy(start)
    bg = replanner(Behind(driver) if mode == "thread" else driver, mode, 0.2)
    try:
        got, _ = _run_through(bg, truth, ticks, at)
    finally:
        bg.close()
    results = {"inline": (expected, inline.driver), mode: (got, bg)}
    (expected, inline), (got, bg) = results["inline"], results[mode]
    assert len(got) == len(expected) == inline.replans >= 2 and bg.replans == inline.replans
    for (traj, ps), (traj_e, ps_e) in zip(got, expected, strict=True):
        assert_same(traj, traj_e)
        assert_same(ps, ps_e)
    assert bg.refused == inline.refused and bg.stopped == inline.stopped
    assert bg.maps_handed == len(inline.map_instants())
    assert np.abs(expected[-1][0].footsteps[:, 2]).max() > 0.25  # the footholds climbed onto the landing
