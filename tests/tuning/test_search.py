"""The search of ``robot tune`` without running it: the candidate grid around the start, the pick (fewest falls,
then the flight closest to the one planned, then the least change from the start), the tuned YAML (the
gait keys written, the robot loads from another folder, the keys reach a scaled live-command scenario), and
the CLI's one-line errors before any work."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from gaitshift.robots import load_robot
from gaitshift.scenario import load_scenario
from gaitshift.tuning.report import report
from gaitshift.tuning.search import (
    FLIGHT_FACTORS,
    FLIGHT_REACHED,
    STEP_TIME_SCALES,
    Candidate,
    TuneResult,
    candidates,
    pick,
    robot_yaml,
)
from gaitshift.tuning.start import StartingGait
from gaitshift.wholebody.scaling import scale_scenario

START = StartingGait(flight_scale=0.6, knee_ratio=1.9, max_yaw_rate=0.3, yaw_joints=("a", "b"))


def test_the_grid_is_every_flight_factor_by_every_step_time_scale():
    grid = candidates(START)
    assert len(grid) == len(FLIGHT_FACTORS) * len(STEP_TIME_SCALES)
    assert {round(c.flight_scale, 6) for c in grid} == {round(0.6 * f, 6) for f in FLIGHT_FACTORS}
    assert all(c.max_yaw_rate == 0.3 for c in grid)


def _rows(c: Candidate, falls: int) -> list[dict]:
    return [{"scenario": f"{c.name}/s{k}.yaml", "fell": k < falls, "error": None} for k in range(4)]


def test_the_pick_is_the_fewest_falls_then_the_least_change():
    grid = candidates(START)
    start_like = next(c for c in grid if c.flight_scale == 0.6 and c.step_time_scale == 1.0)
    quicker = next(c for c in grid if c.flight_scale == 0.6 and c.step_time_scale == 0.75)
    rows = [r for c in grid for r in _rows(c, 1 if c in (start_like, quicker) else 2)]
    assert pick(rows, grid, START) == start_like  # both fall once: the start wins on change
    rows = [r for c in grid for r in _rows(c, 0 if c == quicker else 1)]
    assert pick(rows, grid, START) == quicker  # fewer falls beat a smaller change


def _flown(c: Candidate, ratio: float) -> list[dict]:
    """No fall; a walk (no flight planned: no ratio) and a run that achieved ``ratio`` of its flight."""
    walk = {"scenario": f"{c.name}/walk.yaml", "fell": False, "error": None, "flight_ratio": None}
    return [walk, {"scenario": f"{c.name}/run.yaml", "fell": False, "error": None, "flight_ratio": ratio}]


def test_at_equal_falls_the_pick_is_a_candidate_that_reaches_its_planned_flight():
    grid = candidates(START)
    start_like = next(c for c in grid if c.flight_scale == 0.6 and c.step_time_scale == 1.0)
    shorter = next(c for c in grid if c.flight_scale == 0.15 and c.step_time_scale == 1.0)
    short, reached = FLIGHT_REACHED - 0.01, FLIGHT_REACHED
    rows = [r for c in grid for r in _flown(c, reached if c == shorter else short)]
    assert pick(rows, grid, START) == shorter  # the start's flight is not taken: the flight the robot reaches
    rows = [r for c in grid for r in _flown(c, reached)]
    assert pick(rows, grid, START) == start_like  # every flight reached: the least change again
    text = report(TuneResult(START, grid, pick(rows, grid, START), rows), "r.yaml")
    assert f"flight >= {reached:.2f} of planned" in text and "No candidate" not in text
    rows = [r for c in grid for r in _flown(c, 0.5 if c == shorter else 0.3)]
    assert pick(rows, grid, START) == shorter  # none reaches its flight: the closest one (the OP3's case)
    text = report(TuneResult(START, grid, pick(rows, grid, START), rows), "r.yaml")
    assert f"No candidate's running achieved {FLIGHT_REACHED:.0%}" in text


def test_the_tuned_yaml_loads_elsewhere_and_its_keys_reach_a_scaled_scenario(tmp_path):
    text = (resources.files("gaitshift.robots") / "configs" / "t1.yaml").read_text()
    keys = Candidate(0.4, 0.75, 0.25).keys()
    out = tmp_path / "elsewhere" / "t1-tuned.yaml"
    out.parent.mkdir()
    out.write_text(robot_yaml(text.replace("name: t1", "name: t1x"), keys, Path("/nonexistent")))
    robot = load_robot(out)
    assert (robot.flight_scale, robot.step_time_scale, robot.max_yaw_rate) == (0.4, 0.75, 0.25)
    tour = scale_scenario(load_scenario("g1-tour"), robot)
    assert tour.limits.max_yaw_rate == 0.25


def test_a_bad_robot_or_output_is_one_line_before_any_work(cli, tmp_path):
    work = tmp_path / "work"
    code, _out, err = cli(
        ["robot", "tune", str(tmp_path / "nope.yaml"), "--out", str(tmp_path / "t.yaml"), "--work", str(work)]
    )
    assert code == 2 and err.count("\n") == 1 and "no such file" in err and not work.exists()
    code, _out, err = cli(["robot", "tune", "t1.yaml", "--out", str(tmp_path / "t.txt"), "--work", str(work)])
    assert code == 2 and err.count("\n") == 1 and "--out" in err and not work.exists()
