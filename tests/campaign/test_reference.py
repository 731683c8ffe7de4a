"""The ``reference`` task writes whole-body motions and an index: the motion's velocities are the
time derivatives of its positions (central differences), a faster command carries the pelvis farther
in the same time, and the index names robot, gait, speed, yaw rate, duration and an existing file.
What a case returns holds only builtins and numeric arrays (no MuJoCo object crosses a process).
Cases run in-process here (the Dask path is tested in test_run.py)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np

from gaitshift.campaign.cases import expand
from gaitshift.campaign.execute import run_case
from gaitshift.campaign.spec import load_spec
from gaitshift.campaign.store import INDEX_COLUMNS, Store
from gaitshift.scenario import load_scenario

WALK = Path(__file__).resolve().parents[2] / "docs" / "campaigns" / "g1-walk.yaml"


def _plain(obj) -> bool:
    """Only builtins and numeric numpy arrays: what crosses the worker boundary holds no MuJoCo object."""
    if isinstance(obj, dict):
        return all(isinstance(k, str) and _plain(v) for k, v in obj.items())
    if isinstance(obj, list | tuple):
        return all(_plain(v) for v in obj)
    if isinstance(obj, np.ndarray):
        return obj.dtype.kind in "biuf"
    return obj is None or isinstance(obj, str | int | float | bool)


def _run(tmp_path: Path, mode: str, speeds: list[float]) -> tuple[Store, list[dict]]:
    spec = load_spec(
        {
            "task": "reference",
            "duration": 1.0,
            "reference": {"mode": mode, "rate": 50.0},
            "axes": {"scenario": [str(WALK)], "speed": speeds, "yaw_rate": [0.0]},
        }
    )
    store = Store(tmp_path / mode)
    store.start(mode)
    cases = expand(spec)
    sc = load_scenario(WALK)
    for c in cases:
        result = run_case(c, sc)
        assert _plain(c) and _plain(result)
        store.write(result)
    assert store.finish({c["case_hash"] for c in cases})
    with open(store.root / "index.csv") as fh:
        return store, list(csv.DictReader(fh))


def _check_motion(path: Path, tol: float) -> np.ndarray:
    """Central differences of the base position match the logged base velocity; return qpos."""
    m = np.load(path)
    t, q, v = m["t"], m["qpos"], m["qvel"]
    assert q.shape[0] == v.shape[0] == t.shape[0] > 10 and np.all(np.isfinite(q))
    fd = (q[2:, :3] - q[:-2, :3]) / (t[2:] - t[:-2])[:, None]
    assert np.max(np.abs(fd - v[1:-1, :3])) < tol
    meta = json.loads(str(m["meta"]))
    assert len(meta["qpos_names"]) == q.shape[1]
    return np.asarray(q)


def test_kinematic_library_and_index(tmp_path):
    """Two speeds by IK: index rows with every column, the faster motion goes farther."""
    store, index = _run(tmp_path, "kinematic", [0.3, 0.6])
    assert len(index) == 2 and tuple(index[0]) == INDEX_COLUMNS
    reach = {}
    for row in index:
        assert row["robot"] == "g1" and row["gait"] == "walk" and float(row["duration"]) > 1.0
        q = _check_motion(store.root / row["file"], tol=0.05)
        reach[float(row["speed"])] = q[-1, 0] - q[0, 0]
    assert reach[0.6] > reach[0.3] > 0


def test_closed_loop_motion_is_the_simulated_robot(tmp_path):
    """Closed loop: the motion is the simulated robot's (the row says it did not fall) at 50 Hz; its
    velocities match its positions to the subsampling error."""
    store, index = _run(tmp_path, "closed-loop", [0.4])
    (row,) = store.table().to_pylist()
    assert row["fell"] is False and row["motion_file"] == index[0]["file"]
    q = _check_motion(store.root / index[0]["file"], tol=0.08)
    assert q[-1, 0] - q[0, 0] > 0.2
