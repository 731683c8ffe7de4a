"""The campaign's ``terrain`` axis says what the planner is told of the terrain, as ``simulate --terrain``:
it expands to its values and refuses others in one line naming the field; a case at its default keeps
the hash it had when the axis was the floor (``flat``); the value reaches the simulation (told the step,
the G1 climbs it; blind, it trips on it), the row carries it and the elevation map's numbers; a
scenario that refuses the value gives an error row, not a crash; an older store reads with the new
columns null; the report breaks survival down by terrain and tabulates the map's numbers."""

from __future__ import annotations

import itertools
import sys
from pathlib import Path

import pyarrow.parquet as pq
import pytest

from gaitshift.campaign.breakdown import axis_survival, breakdown_markdown
from gaitshift.campaign.cases import expand
from gaitshift.campaign.execute import run_case
from gaitshift.campaign.spec import load_spec
from gaitshift.campaign.store import SCHEMA, Store
from gaitshift.errors import InputError
from gaitshift.scenario import load_scenario

ROOT = Path(__file__).resolve().parents[2]
WALK = ROOT / "docs" / "campaigns" / "g1-walk.yaml"
sys.path.insert(0, str(ROOT / "benchmarks"))

#: one 10 cm step up onto a landing, 0.25 m ahead (g1-stairs-up's first tread), three steps: 5 s of plan
STEP_UP = """
planner: tvlip
robot: g1
height: 0.58
timing: {single_support: 0.60, double_support: 0.20, flight: 0.12, start: 0.8, stop: 1.0}
foot: {size: [0.17, 0.05], zmp_margin: 0.01}
gait: [{gait: walk, steps: 3}]
profile: {max_stride: 0.25, accelerate_steps: 1, decelerate_steps: 1, step_width: 0.237}
swing_height: 0.06
edge_clearance: 0.03
terrain: [{x: [0.25, 3.00], z: [0.1, 0.1]}]
"""


def _spec(tmp_path: Path, **axes) -> object:
    (tmp_path / "step.yaml").write_text(STEP_UP)
    return load_spec({"task": "simulate", "base": str(tmp_path), "axes": {"scenario": ["step.yaml"], **axes}})


def test_the_axis_expands_to_its_values_and_defaults_to_the_scenarios(tmp_path):
    cases = expand(_spec(tmp_path, terrain=["known", "blind", "perceived"], seed=[0, 1]))
    assert [c["terrain"] for c in cases] == ["known", "known", "blind", "blind", "perceived", "perceived"]
    assert len({c["case_hash"] for c in cases}) == 6
    assert [c["terrain"] for c in expand(_spec(tmp_path))] == [None]  # not swept: the scenario's sim.terrain


def test_the_shipped_spec_crosses_every_perception_scenario_with_every_terrain():
    """docs/campaigns/g1-terrain.yaml (the crossing benchmark's campaign): the scenarios of
    docs/perception/ x known, blind, perceived x seeds 0-2."""
    cases = expand(load_spec(ROOT / "docs" / "campaigns" / "g1-terrain.yaml"))
    scenarios = {Path(c["scenario"]).name for c in cases}
    assert scenarios == {p.name for p in (ROOT / "docs" / "perception").glob("*-ahead.yaml")}
    assert len(cases) == len(scenarios) * 3 * 3 and {c["terrain"] for c in cases} == {"known", "blind", "perceived"}


def test_the_builtins_spec_holds_every_g1_builtin_on_terrain_perceived():
    """docs/campaigns/g1-terrain-builtins.yaml (docs/perception.md, "perceived as the default"): every
    built-in G1 scenario whose world has terrain, left to perceive it, seeds 0-2."""
    from gaitshift.scenario.loader import builtin_names, load_scenario

    on_terrain = {n for n in builtin_names() if n.startswith("g1-") and getattr(load_scenario(n), "terrain", ())}
    cases = expand(load_spec(ROOT / "docs" / "campaigns" / "g1-terrain-builtins.yaml"))
    assert {c["scenario"] for c in cases} == on_terrain and len(on_terrain) >= 7
    assert len(cases) == 3 * len(on_terrain) and {c["terrain"] for c in cases} == {"perceived"}


@pytest.mark.parametrize(
    ("task", "values", "field", "words"),
    [
        ("simulate", ["known", "flat"], "axes.terrain[1]", "one of: known, blind, perceived"),
        ("simulate", [True], "axes.terrain[0]", "one of: known, blind, perceived"),
        ("plan", ["blind"], "axes.terrain", "no value unless the task simulates"),
    ],
)
def test_a_bad_terrain_is_one_input_error_naming_the_field(task, values, field, words):
    with pytest.raises(InputError) as exc:
        load_spec({"task": task, "axes": {"scenario": [str(WALK)], "terrain": values}})
    assert exc.value.field == field and words in str(exc.value) and "\n" not in str(exc.value)


def test_a_case_at_the_default_terrain_keeps_the_hash_it_had_when_the_axis_was_the_floor():
    """docs/robustness.md names survival case ``0093c3a7``: its hash was made with ``terrain: flat``."""
    cases = expand(load_spec(ROOT / "docs" / "campaigns" / "g1-survival.yaml"), check=False)
    assert "0093c3a77300be77" in {c["case_hash"] for c in cases}


@pytest.fixture(scope="module")
def step_rows(tmp_path_factory):
    """The step-up scenario told the terrain and blind, through the store (about 8 s)."""
    root = tmp_path_factory.mktemp("terrain")
    spec = _spec(root, terrain=["known", "blind"])
    scenario = load_scenario(spec.scenario_path("step.yaml"))
    store = Store(root / "out")
    store.start("terrain")
    for case in expand(spec):
        store.write(run_case(case, scenario))
    return {r["terrain"]: r for r in store.table().to_pylist()}


def test_the_terrain_reaches_the_simulation_told_it_climbs_blind_it_trips(step_rows):
    """Known, the plan lifts the foot onto the 10 cm step and the G1 stands on the landing; blind, the
    plan puts the foot at the floor's height inside the step's riser, and it falls."""
    known, blind = step_rows["known"], step_rows["blind"]
    assert known["error"] is None and blind["error"] is None
    assert not known["fell"] and known["end_x"] > 0.4
    assert blind["fell"] and 2.0 < blind["t_fall"] < 5.0


def test_the_rows_carry_the_elevation_maps_numbers(step_rows):
    """The G1 has a head depth camera: every run maps the ground, so the map's error under the feet, its
    coverage and the soles' distance from the step's edge are columns; known and blind do not re-plan
    (the perceived driver's refusals are null: there is none). The map of the robot that stands is right
    to a centimetre under its feet; the blind one's falls with it (its estimate tumbling), so it is only
    present, or null with a coverage of 0 when the robot fell before any mapped cell lay under its feet
    (blind, it trips at 2.7 s since the swing references carry the step correction's rates)."""
    known = step_rows["known"]
    assert 0 < known["map_error_median"] <= known["map_error_p95"] < 0.01 and 0 < known["map_coverage"] <= 1
    for row in step_rows.values():
        assert 0 <= row["map_coverage"] <= 1
        if row["map_coverage"] == 0:
            assert row["map_error_median"] is None and row["map_error_p95"] is None
        else:
            assert 0 < row["map_error_median"] <= row["map_error_p95"] < 1.0
        assert row["map_frames"] > 50 and row["edge_distance_min"] < row["edge_distance_median"] < 1.0
        assert row["replans"] == 0 and row["replans_refused"] is None and row["perception_stopped"] is None
    assert step_rows["known"]["edge_distance_min"] > 0 > step_rows["blind"]["edge_distance_min"]  # across it


def test_the_crossing_benchmark_prints_the_campaigns_rows(step_rows):
    from perception_crossings import crossing, table

    rows = [crossing(step_rows[k]) for k in ("known", "blind")]
    text = table(rows)
    assert "| step | known | 0 | no fall, pelvis ends at x = " in text
    assert "| step | blind | 0 | falls at " in text and text.count("\n") == 3


def test_a_scenario_that_refuses_the_value_is_an_error_row(tmp_path):
    """``perceived`` on a live-command scenario (its generator plans on flat ground): the case's row
    holds the one-line reason and no metrics; the campaign's other case (blind) ran."""
    axes = {"scenario": [str(WALK)], "terrain": ["blind", "perceived"]}
    spec = load_spec({"task": "simulate", "duration": 0.6, "axes": axes})
    rows = {c["terrain"]: run_case(c, load_scenario(WALK))["row"] for c in expand(spec)}
    bad = rows["perceived"]
    assert "perceived" in bad["error"] and "tvlip" in bad["error"] and "\n" not in bad["error"]
    assert bad["fell"] is None and bad["map_error_median"] is None and bad["end_x"] is None
    assert rows["blind"]["error"] is None and rows["blind"]["fell"] is False


def test_an_older_store_reads_with_the_new_columns_null(tmp_path):
    """A part of the first G1 map (2026-11-23: ``terrain`` was ``flat``, no map columns) reads in the
    current schema: its terrain as written, the perception columns null."""
    table = pq.read_table(ROOT / "docs" / "campaigns" / "g1-500-results.parquet")
    (tmp_path / "parts").mkdir()
    pq.write_table(table.slice(0, 1), tmp_path / "parts" / f"{table['case_hash'][0]}.parquet")
    (row,) = Store(tmp_path).table().to_pylist()
    assert Store(tmp_path).table().schema.equals(SCHEMA) and row["terrain"] == "flat"
    assert all(row[k] is None for k in ("end_x", "replans", "map_error_median", "edge_distance_min"))


def _rows() -> list[dict]:
    """Two scenarios x three terrains x 12 seeds: blind falls on the stairs, the rest stands."""
    rows = []
    grid = itertools.product(("a/stairs.yaml", "a/ramp.yaml"), ("known", "blind", "perceived"), range(12))
    for i, (sc, terrain, seed) in enumerate(grid):
        fell = sc == "a/stairs.yaml" and terrain == "blind"
        values = {"scenario": sc, "terrain": terrain, "seed": seed, "fell": fell, "case_hash": str(i)}
        rows.append(dict.fromkeys(SCHEMA.names) | values | {"map_error_median": 0.004, "replans": 3})
    return rows


def test_the_report_breaks_survival_down_by_terrain_and_tabulates_the_map():
    rows = _rows()
    assert axis_survival(rows, "terrain") == [("blind", 24, 0.5), ("known", 24, 1.0), ("perceived", 24, 1.0)]
    md = "\n".join(breakdown_markdown(rows))
    assert "- `terrain`: blind: 50 % (24), known: 100 % (24)" in md
    assert "| scenario | terrain | a/stairs.yaml | blind | 12 | 0 % |" in md  # the worst pair cell
    assert "| stairs | blind | 12 | 0 of 12 | - | 4.0 / - | - / - | 3 |" in md
