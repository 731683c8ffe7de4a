"""``gaitshift robot tune``: a new robot's gait keys found by a small campaign, not by hand.

From the model-derived start (:mod:`gaitshift.tuning.start`) the search tries a grid of candidate
``gait`` keys::

    flight_scale     = start x FLIGHT_FACTORS          (the knee's estimate, and shorter flights)
    step_time_scale  = STEP_TIME_SCALES                (quicker, shorter steps: less lateral sway)
    max_yaw_rate     = start                           (the yaw joints' speed, eq. (2) of start.py)

Each candidate is the robot YAML with those keys, written to the work folder; the G1's walk, run,
walk-run-walk and live-command tour are scaled to it (:func:`gaitshift.wholebody.scaling.scale_scenario`,
which applies the keys) and simulated closed loop on the estimated state with ``typical`` noise over
the seeds, as one campaign (Dask, :mod:`gaitshift.campaign`): an interrupted tune resumes. A candidate's
score is, in order:

1. its falls (fewer first);
2. how far its runs' achieved flights fall short of :data:`FLIGHT_REACHED` of the planned ones (the sum of
   ``max(0, FLIGHT_REACHED - flight_ratio)`` over the runs that plan a flight, smaller first): a flight the
   robot does not take is not the flight it can reach (a stance planned after a flight that does not
   happen lands early), and where no candidate reaches it the one that comes closest wins;
3. how far it departs from the start (the sum of ``|log(key / start key)|``: the least change that holds).

The tuned YAML is the robot YAML with the winner's keys; the report lists every candidate's runs, and says
so when no candidate reaches the flight it plans.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from gaitshift.errors import InputError
from gaitshift.robots.config import RobotConfig, load_robot
from gaitshift.tuning.start import StartingGait, starting_gait

__all__ = [
    "FLIGHT_FACTORS", "FLIGHT_REACHED", "SCENARIOS", "STEP_TIME_SCALES", "Candidate", "candidates", "flight_short",
    "pick", "tune",
]  # fmt: skip

#: the G1 scenarios every candidate runs (scaled to the robot)
SCENARIOS = ("g1-walk", "g1-run", "g1-walk-run-walk", "g1-tour")
#: factors on the start's flight scale
FLIGHT_FACTORS = (1.0, 0.5, 0.25)
#: step time scales tried
STEP_TIME_SCALES = (1.0, 0.75)
#: the share of its planned flight a run must achieve for the candidate to reach its flight (issue 26's
#: bar for the OP3's running)
FLIGHT_REACHED = 0.7


@dataclass(frozen=True)
class Candidate:
    """One set of gait keys: ``flight_scale``, ``step_time_scale`` and ``max_yaw_rate`` (rad/s or None)."""

    flight_scale: float
    step_time_scale: float
    max_yaw_rate: float | None

    @property
    def name(self) -> str:
        return f"f{self.flight_scale:.3f}-s{self.step_time_scale:.2f}"

    def keys(self) -> dict[str, float]:
        """The ``gait`` keys (robot YAML) of the candidate."""
        out = {"flight_scale": round(self.flight_scale, 4), "step_time_scale": self.step_time_scale}
        if self.max_yaw_rate is not None:
            out["max_yaw_rate"] = round(self.max_yaw_rate, 4)
        return out

    def change(self, start: StartingGait) -> float:
        """How far the candidate departs from the start: sum of |log| of the keys' ratios."""
        return abs(math.log(self.flight_scale / start.flight_scale)) + abs(math.log(self.step_time_scale))


def candidates(start: StartingGait) -> list[Candidate]:
    """The grid of the module docstring."""
    return [
        Candidate(min(1.0, start.flight_scale * f), s, start.max_yaw_rate)
        for f, s in itertools.product(FLIGHT_FACTORS, STEP_TIME_SCALES)
    ]


def flight_short(row: dict[str, Any]) -> float:
    """How far a run's achieved flight falls short of :data:`FLIGHT_REACHED` of its planned one, a share of
    the planned flight (0: reached, or no flight planned: ``flight_ratio`` None)."""
    ratio = row.get("flight_ratio")
    return 0.0 if ratio is None else max(0.0, FLIGHT_REACHED - float(ratio))


def pick(rows: Sequence[dict[str, Any]], grid: Sequence[Candidate], start: StartingGait) -> Candidate:
    """The candidate of the best score (module docstring) over ``rows`` (campaign rows whose ``scenario``
    names the candidate's folder): the fewest falls, then the smallest flight shortfall, then the least
    change from ``start``."""
    falls = {c.name: 0 for c in grid}
    short = {c.name: 0.0 for c in grid}
    for r in rows:
        name = Path(r["scenario"]).parent.name
        falls[name] += int(bool(r["fell"])) + int(r.get("error") is not None)
        short[name] += flight_short(r)
    return min(grid, key=lambda c: (falls[c.name], short[c.name], c.change(start)))


def robot_yaml(text: str, keys: dict[str, float], base: Path) -> str:
    """The robot YAML ``text`` with its ``gait`` keys updated by ``keys`` and its ``mjcf`` path made
    absolute against ``base`` (the original YAML's folder), so the file can live elsewhere."""
    data = yaml.safe_load(text)
    data["gait"] = {**(data.get("gait") or {}), **keys}
    mjcf = str(data["mjcf"])
    if not mjcf.startswith("asset:") and not Path(mjcf).is_absolute():
        data["mjcf"] = str((base / mjcf).resolve())
    return yaml.safe_dump(data, sort_keys=False, default_flow_style=None, width=110)


@dataclass(frozen=True)
class TuneResult:
    """What a tune found: the start, the grid, the winner, and every campaign row."""

    start: StartingGait
    grid: list[Candidate]
    best: Candidate
    rows: list[dict[str, Any]]


def tune(
    robot_path: Path, work: Path, seeds: Sequence[int] = (0,), workers: int | None = None,
    scenarios: Sequence[str] = SCENARIOS,
) -> TuneResult:  # fmt: skip
    """Tune the robot YAML at ``robot_path`` in the folder ``work`` (module docstring)."""
    from gaitshift.campaign.run import run_campaign
    from gaitshift.campaign.spec import load_spec
    from gaitshift.campaign.store import Store

    robot = load_robot(robot_path)  # a bad YAML: its one-line error before any work
    text = robot_path.read_text()
    start = starting_gait(robot)
    grid = candidates(start)
    names = [_candidate_scenarios(work, c, text, robot_path.resolve().parent, scenarios) for c in grid]
    spec_data = {
        "name": f"tune-{robot.name}",
        "task": "simulate",
        "axes": {"scenario": [n for ns in names for n in ns], "seed": list(seeds), "state": ["estimated"]},
    }
    spec_text = yaml.safe_dump(spec_data, sort_keys=False)
    (work / "spec.yaml").write_text(spec_text)
    run_campaign(load_spec(work / "spec.yaml"), spec_text, work / "runs", workers=workers)
    rows = Store(work / "runs").table().to_pylist()
    return TuneResult(start, grid, pick(rows, grid, start), rows)


def _candidate_scenarios(work: Path, c: Candidate, text: str, base: Path, scenarios: Sequence[str]) -> list[str]:
    """Write the candidate's robot YAML and its scaled scenarios; their paths relative to ``work``."""
    from gaitshift.wholebody.scaling import scaled_yaml

    folder = work / c.name
    folder.mkdir(parents=True, exist_ok=True)
    robot_file = folder / "robot.yaml"
    robot_file.write_text(robot_yaml(text, c.keys(), base))
    cfg: RobotConfig = load_robot(robot_file)
    out = []
    for name in scenarios:
        path = folder / f"{name}.yaml"
        if not path.exists():
            path.write_text(scaled_yaml(name, cfg, folder)[0])
        out.append(f"{c.name}/{path.name}")
    return out


def check_seeds(seeds: Sequence[int]) -> list[int]:
    """Seeds as given, each an integer >= 0; :class:`InputError` otherwise."""
    for s in seeds:
        if isinstance(s, bool) or not isinstance(s, int) or s < 0:
            raise InputError("--seed", s, "integers >= 0")
    return list(seeds)
