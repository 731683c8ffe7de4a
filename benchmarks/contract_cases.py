"""The surfaces of the error contract and one random case builder each (benchmarks/contract_sample.py).

A builder ``build(rng, folder, base) -> Case`` draws one case from a ``random.Random`` into its own
empty ``folder``; ``base`` (:class:`Base`) holds the files every case may start from (valid plans,
joints, a campaign dataset), made once. A case is a command line of ``gaitshift`` or a call of the
Python API, the files a success writes, the names its one-line refusal may use, and the exit codes
allowed (0 result, 1 a result that reports a failure, 2 refused). Builders of commands that run long on
valid input (simulate, wholebody, animate, export, campaign runs) make only inputs that must be
refused (exit 2 alone is allowed), so no case runs a simulation.
"""

from __future__ import annotations

import json
import random
import shutil
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import yaml

import gaitshift
from contract_mutate import (
    FLAG_TEXT,
    damage_bytes,
    damage_text,
    garbage,
    mutate,
    schema_names,
)
from gaitshift.campaign.axes import AXES
from gaitshift.campaign.spec import CampaignSpec
from gaitshift.robots.schema import RobotYaml
from gaitshift.scenario.loader import SCHEMAS

ROOT = Path(__file__).resolve().parents[1]
ROBOTS = ROOT / "src" / "gaitshift" / "robots" / "configs"


@dataclass
class Case:
    """One contract case (module docstring). ``argv``: a CLI case; else ``call`` is called."""

    surface: str
    names: set[str]
    argv: list[str] | None = None
    call: Callable[[], Any] | None = None
    outputs: tuple[Path, ...] = ()
    codes: tuple[int, ...] = (0, 2)
    note: str = ""
    extra: dict[str, Any] = field(default_factory=dict)


# ====================================================================== base inputs
TVLIP = {
    "gait": [{"gait": "walk", "steps": 1}, {"gait": "run", "steps": 2}, {"gait": "walk", "steps": 1}],
    "timing": {"single_support": 0.4, "double_support": 0.15, "flight": 0.15, "start": 0.5, "stop": 0.5},
    "foot": {"size": [0.22, 0.12], "zmp_margin": 0.01, "zmp_z": [0.0, 0.0]},
    "profile": {"max_stride": 0.4, "accelerate_steps": 1, "decelerate_steps": 1, "step_width": 0.2},
    "limits": {"max_stride": 1.0, "max_step_height": 0.25},
    "height": 0.95,
    "dt": 0.01,
}
VHIP = {
    "planner": "vhip",
    "dt": 0.004,
    "step_period": 0.4,
    "stance_ratio": 0.7,
    "start_double_support": 0.4,
    "stop_double_support": 0.4,
    "heights": {"stand": 0.8, "touchdown": 0.8, "takeoff": 0.8, "z_low": 0.76},
    "commands": [{"t": 0.0, "vx": 0.3, "vy": 0.0}, {"t": 0.4, "vx": 0.6, "vy": 0.1}],
    "stop_at": 0.8,
    "limits": {"max_speed": [1.5, 0.2], "max_stride": 0.8, "max_accel_per_step": [0.3, 0.2]},
}
LOCOMOTION = {
    "planner": "locomotion",
    "robot": "g1",
    "gait": "auto",
    "commands": [{"t": 0.0, "vx": 0.4}, {"t": 0.4, "vx": 0.6, "yaw_rate": 0.3}],
    "stop_at": 0.8,
    "dt": 0.005,
    "switch": {"walk_to_run": 0.82, "run_to_walk": 0.64},
    "timing": {"start": 0.4, "stop": 0.4},
    "limits": {"max_speed": [1.5, 0.3, 1.0]},
}
SPEC = {
    "name": "fuzz",
    "task": "plan",
    "duration": 2.0,
    "axes": {
        "scenario": ["g1-walk.yaml"],
        "speed": {"start": 0.2, "stop": 0.8, "step": 0.3},
        "push_impulse": [0, 6],
        "mass_scale": [0.9, 1.1],
        "friction": [0.4, 1.0],
        "state": ["oracle"],
    },
}
SCENARIO_NAMES = set().union(*(schema_names(m) for m in SCHEMAS.values())) | {"scenario", "planner", "file"}
ROBOT_NAMES = schema_names(RobotYaml) | {"robot", "mjcf", "file", "yaml"}
SPEC_NAMES = schema_names(CampaignSpec) | set(AXES) | {"spec", "axes", "file"}


@dataclass
class Base:
    """Files the cases start from, made once in ``folder`` (a few seconds)."""

    folder: Path
    plans: dict[str, bytes] = field(default_factory=dict)
    joints: bytes = b""
    campaign: Path | None = None

    @classmethod
    def make(cls, folder: Path) -> Base:
        folder.mkdir(parents=True, exist_ok=True)
        base = cls(folder)
        for name, data in (("tvlip", TVLIP), ("vhip", VHIP), ("locomotion", LOCOMOTION)):
            traj = gaitshift.plan(gaitshift.load_scenario(data))
            for suffix in (".npz", ".csv", ".json"):
                base.plans[name + suffix] = traj.save(folder / f"{name}{suffix}").read_bytes()
        t = np.linspace(0, 1, 11)
        joints = folder / "joints.npz"
        np.savez(joints, t=t, qpos=np.zeros((11, 36)), qvel=np.zeros((11, 35)), meta=np.array('{"robot": "g1"}'))
        base.joints = joints.read_bytes()
        base.campaign = _campaign_folder(folder / "campaign")
        (folder / "vhip.yaml").write_text(yaml.safe_dump(VHIP))
        (folder / "tvlip.yaml").write_text(yaml.safe_dump(TVLIP))
        return base


def _campaign_folder(folder: Path) -> Path:
    """A campaign dataset of 12 rows of the shipped G1 map (docs/campaigns)."""
    import pyarrow.parquet as pq

    table = pq.read_table(ROOT / "docs" / "campaigns" / "g1-500-results.parquet")
    (folder / "parts").mkdir(parents=True, exist_ok=True)
    for i in range(0, 500, 42):
        pq.write_table(table.slice(i, 1), folder / "parts" / f"{table['case_hash'][i]}.parquet")
    shutil.copy(ROOT / "docs" / "campaigns" / "g1-500-subset.yaml", folder / "spec.yaml")
    return folder


def with_fixtures(folder: Path) -> None:
    """The files an output-name case may collide with: a file ``file.npz`` and a folder ``dir.npz``."""
    (folder / "file.npz").write_bytes(b"x")
    (folder / "dir.npz").mkdir(exist_ok=True)


def _flag(rng: random.Random, valid: str) -> str:
    return valid if rng.random() < 0.75 else rng.choice([*FLAG_TEXT, repr(rng.uniform(-1e3, 1e3))])


# ====================================================================== CLI surfaces
def stiffness_case(rng: random.Random, folder: Path, base: Base) -> Case:
    valid = {"--height": "0.95", "--single-support": "0.4", "--double-support": "0.15", "--flight": "0.15"}
    argv = ["stiffness", "--json"]
    for flag, value in valid.items():
        argv += [flag, _flag(rng, value)]
    if rng.random() < 0.5:
        argv += ["--gravity", _flag(rng, "9.81")]
    names = {*valid, "--gravity"} | {f.lstrip("-").replace("-", "_") for f in valid} | {"gravity"}
    return Case("stiffness", names, argv=argv, extra={"json": True})


def _scenario_case(surface: str, data: dict[str, Any], rng: random.Random, folder: Path) -> Case:
    edits = rng.choice([0, 0, 1, 1, 2, 3])
    doc, added = mutate(data, rng, edits)
    path = folder / rng.choice(["s.yaml", "s.yml", "s.YAML"])
    path.write_bytes(damage_text(yaml.safe_dump(doc, allow_unicode=True), rng))
    suffix = rng.choice([".npz", ".csv", ".json", ".npz", ".NPZ", ".Json", ".txt", ""])
    out = folder / f"plan{suffix}"
    return Case(
        surface, SCENARIO_NAMES | added | {"--out"}, argv=["plan", str(path), "--out", str(out)], outputs=(out,)
    )


def scenario_case(rng: random.Random, folder: Path, base: Base) -> Case:
    data = rng.choice([TVLIP, VHIP])
    return _scenario_case("scenario", data, rng, folder)


def locomotion_case(rng: random.Random, folder: Path, base: Base) -> Case:
    return _scenario_case("locomotion", LOCOMOTION, rng, folder)


def trajectory_case(rng: random.Random, folder: Path, base: Base) -> Case:
    name = rng.choice(sorted(base.plans))
    raw = base.plans[name]
    path = folder / f"traj{Path(name).suffix}"
    if rng.random() < 0.5 or path.suffix == ".npz":
        raw = damage_bytes(raw, rng) if rng.random() < 0.8 else raw
        path.write_bytes(raw)
    else:  # a structural edit of the JSON document, or of a CSV header line
        text = raw.decode()
        if path.suffix == ".json":
            doc, _ = mutate(json.loads(text), rng, rng.choice([1, 2]))
            path.write_text(json.dumps(doc))
        else:
            lines = text.split("\n")
            i = rng.randrange(min(len(lines), 8))
            lines[i] = lines[i][: rng.randrange(len(lines[i]) + 1)] + rng.choice(["", "x", ",1e999", ",nan", "]"])
            path.write_text("\n".join(lines))
    names = {"file", "meta", "header", "row", "column", "extras"} | set(gaitshift.Trajectory.__dataclass_fields__)
    return Case("trajectory", names, argv=["check", str(path), "--json"], codes=(0, 1, 2), extra={"json": True})


def teleop_case(rng: random.Random, folder: Path, base: Base) -> Case:
    tokens = ["up", "down", "left", "right", "space", "q", "wait=0.3", "wait=1", "UP", "wait=-1", "wait=nan", "x"]
    script = rng.choice([" ", ",", ";", "\n"]).join(rng.choice(tokens) for _ in range(rng.randrange(6)))
    max_time = rng.choice(["1.5"] * 5 + ["nan", "-1", "0", "inf", "1e9", "abc"])
    out = folder / f"teleop{rng.choice(['.npz', '.csv', '.json', '.txt', ''])}"
    argv = ["teleop", str(base.folder / "vhip.yaml"), "--script", script, "--max-time", max_time, "--out", str(out)]
    return Case("teleop", {"--script", "--max-time", "--out"}, argv=argv, outputs=(out,))


def fill_placeholders(arg: str, fill: dict[str, str]) -> str:
    """``arg`` with every placeholder of ``fill`` (``{plan}``, ``{folder}``, ...) replaced."""
    for k, v in fill.items():
        arg = arg.replace(k, v)
    return arg


def robot_case(rng: random.Random, folder: Path, base: Base) -> Case:
    name = rng.choice(["op3", "berkeley", "t1", "g1", "h1"])
    doc = yaml.safe_load((ROBOTS / f"{name}.yaml").read_text())
    if rng.random() < 0.15:  # the sole frame: a quaternion per side, any of them degenerate
        quat = rng.choice([[0, 0, 0, 0], [1, 0, 0, 0], [1e-9, 0, 0, 0], [float("nan"), 0, 0, 1], [2, 0, 0, 0]])
        doc["sole_orientation"] = {"left": quat, "right": rng.choice([quat, [1, 0, 0, 0]])}
        added: set[str] = set()
    else:
        doc, added = mutate(doc, rng, rng.choice([0, 1, 1, 2]))
    path = folder / "robot.yaml"
    path.write_bytes(damage_text(yaml.safe_dump(doc, allow_unicode=True), rng))
    return Case("robot", ROBOT_NAMES | added, argv=["robot", "check", str(path)], codes=(0, 1, 2))


def spec_case(rng: random.Random, folder: Path, base: Base) -> Case:
    from gaitshift.campaign.cases import expand
    from gaitshift.campaign.spec import load_spec

    shutil.copy(ROOT / "docs" / "campaigns" / "g1-walk.yaml", folder / "g1-walk.yaml")
    doc, added = mutate(SPEC, rng, rng.choice([0, 1, 1, 2, 3]))
    path = folder / "spec.yaml"
    path.write_bytes(damage_text(yaml.safe_dump(doc, allow_unicode=True), rng))
    names = SPEC_NAMES | added
    if rng.random() < 0.3:  # the command line, with a --out that is a file: refused, nothing runs
        with_fixtures(folder)
        argv = ["campaign", str(path), "--out", str(folder / "file.npz")]
        return Case("spec", names | {"--out"}, argv=argv, codes=(2,))
    return Case("spec", names, call=lambda: len(expand(load_spec(path))))


#: damage to a campaign folder: name -> edit of the folder
REPORT_DAMAGE: dict[str, Callable[[Path, random.Random], None]] = {
    "none": lambda d, r: None,
    "stray": lambda d, r: (d / "parts" / r.choice(["notes.txt", ".x.parquet", "README"])).write_text("hi"),
    "stray_dir": lambda d, r: (d / "parts" / r.choice(["sub", "y.parquet"])).mkdir(),
    "part_bytes": lambda d, r: _damage_part(d, r),  # noqa: PLW0108 - the table's one signature
    "part_empty": lambda d, r: (d / "parts" / "e.parquet").write_bytes(b""),
    "part_schema": lambda d, r: _other_schema(d / "parts" / "o.parquet", r),
    "spec": lambda d, r: (d / "spec.yaml").write_bytes(damage_bytes((d / "spec.yaml").read_bytes(), r)),
    "spec_garbage": lambda d, r: (d / "spec.yaml").write_text(yaml.safe_dump(garbage(r))),
    "spec_gone": lambda d, r: (d / "spec.yaml").unlink(),
    "report_file": lambda d, r: (d / "report").write_text("x"),
    "no_parts": lambda d, r: shutil.rmtree(d / "parts"),
    "parts_empty": lambda d, r: [p.unlink() for p in (d / "parts").iterdir()],
}


def _damage_part(folder: Path, rng: random.Random) -> None:
    part = rng.choice(sorted((folder / "parts").iterdir()))
    part.write_bytes(damage_bytes(part.read_bytes(), rng))


def _other_schema(path: Path, rng: random.Random) -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq

    cols = rng.choice([{"fell": ["x"]}, {"speed": ["a"]}, {"a": [1]}, {"fell": [None], "speed": [float("nan")]}])
    pq.write_table(pa.table(cols), path)


def report_case(rng: random.Random, folder: Path, base: Base) -> Case:
    assert base.campaign is not None
    camp = folder / "c"
    shutil.copytree(base.campaign, camp)
    damage = rng.choice(sorted(REPORT_DAMAGE))
    REPORT_DAMAGE[damage](camp, rng)
    names = {"DIR", "spec.yaml", "parts", "campaign folder"}
    return Case("report", names, argv=["campaign", "report", str(camp)], outputs=(camp / "report",), note=damage)


def joints_case(rng: random.Random, folder: Path, base: Base) -> Case:
    path = folder / rng.choice(["j.npz", "j.NPZ"])
    path.write_bytes(damage_bytes(base.joints, rng)[: max(len(base.joints) - 1, 0)])  # never whole
    argv = ["animate", str(base.folder / "tvlip.npz"), "--joints", str(path), "--out", str(folder / "m.mp4")]
    return Case("joints", {"--joints", "file"}, argv=argv, codes=(2,))


def export_case(rng: random.Random, folder: Path, base: Base) -> Case:
    """export on a damaged plan or log (refused before any IK: the source fails to load)."""
    name = rng.choice(sorted(base.plans))
    path = folder / f"src{Path(name).suffix}"
    raw = damage_bytes(base.plans[name], rng)
    path.write_bytes(raw[: max(len(base.plans[name]) - 1, 0)])
    fmt = rng.choice(["unitree-csv", "mjlab-npz", "bvh", ""])
    out = folder / ("m.csv" if fmt == "unitree-csv" else "m.npz")
    argv = ["export", str(path), "--format", fmt, "--out", str(out)]
    if rng.random() < 0.3:
        argv += ["--fps", rng.choice(["0", "-1", "abc", "30", "1e9"])]
    names = {"SOURCE", "--format", "--out", "--fps", "--robot", "file", "meta", "header", "row", "column"}
    names |= set(gaitshift.Trajectory.__dataclass_fields__)
    return Case("export", names, argv=argv, codes=(2,))
