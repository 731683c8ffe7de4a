"""The trajectory file contract round-trips through .npz, .csv and .json, and writes atomically."""

import json

import numpy as np
import pytest

import gaitshift
from gaitshift.errors import InputError
from gaitshift.trajectory import CONTRACT_KEYS, Trajectory


@pytest.fixture(scope="module")
def traj():
    sc = gaitshift.load_scenario({"gait": [{"gait": "walk", "steps": 1}, {"gait": "run", "steps": 2},
                                           {"gait": "walk", "steps": 2}], "dt": 0.01})
    return gaitshift.plan(sc)


@pytest.mark.parametrize("suffix", [".npz", ".csv", ".json"])
def test_every_format_round_trips_every_contract_key(traj, tmp_path, suffix):
    path = traj.save(tmp_path / f"plan{suffix}")
    back = Trajectory.load(path)
    for key in CONTRACT_KEYS:
        if key == "meta":
            assert back.meta == json.loads(json.dumps(traj.meta))
            continue
        a, b = getattr(traj, key), getattr(back, key)
        assert a.shape == b.shape and a.dtype == b.dtype, key
        np.testing.assert_array_equal(np.isnan(a) if a.dtype.kind == "f" else a,
                                      np.isnan(b) if b.dtype.kind == "f" else b)
        if a.dtype.kind == "f":
            np.testing.assert_allclose(a[np.isfinite(a)], b[np.isfinite(b)], rtol=1e-12, atol=0)


def test_npz_matches_the_documented_key_shapes_and_types(traj, tmp_path):
    path = traj.save(tmp_path / "plan.npz")
    with np.load(path) as z:
        n, m = len(z["t"]), len(z["footsteps"])
        shapes = {"t": (n,), "com_pos": (n, 3), "com_vel": (n, 3), "com_acc": (n, 3), "zmp": (n, 3),
                  "phase": (n,), "contact": (n, 2), "foot_pos": (n, 2, 3), "stiffness": (n,),
                  "footsteps": (m, 4), "footstep_side": (m,), "command_vel": (n, 2), "meta": ()}
        for key, shape in shapes.items():
            assert z[key].shape == shape, key
        assert z["phase"].dtype == np.int8 and z["footstep_side"].dtype == np.int8
        assert z["contact"].dtype == bool
        meta = json.loads(str(z["meta"]))
        assert meta["planner"] == "tvlip" and meta["gravity"] == 9.81 and len(meta["foot_size"]) == 2
        assert "scenario" in meta
        assert np.allclose(np.diff(z["t"]), z["t"][1] - z["t"][0])


def test_unknown_suffix_is_rejected_and_writes_nothing(traj, tmp_path):
    with pytest.raises(InputError, match="out"):
        traj.save(tmp_path / "plan.txt")
    assert list(tmp_path.iterdir()) == []


def test_failed_write_leaves_no_partial_file(traj, tmp_path, monkeypatch):
    def boom(*a, **k):
        raise OSError("disk full")

    monkeypatch.setattr(np, "savez_compressed", boom)
    with pytest.raises(OSError):
        traj.save(tmp_path / "plan.npz")
    assert list(tmp_path.iterdir()) == []


def test_csv_keeps_text_that_contains_nan(tmp_path):
    sc = gaitshift.load_scenario({"description": "Hanasaki and Tazaki, nan-free", "gait": [{"gait": "walk", "steps": 1}],
                                  "dt": 0.02})
    back = Trajectory.load(gaitshift.plan(sc).save(tmp_path / "p.csv"))
    assert back.meta["scenario"]["description"] == "Hanasaki and Tazaki, nan-free"
