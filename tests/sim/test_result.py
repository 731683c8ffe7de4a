"""The run file: every array, the fall and strict-JSON metadata (NaN written as null), atomically."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from gaitshift.errors import InputError
from gaitshift.sim.result import SimResult


def _result(fell):
    arrays = {"t": np.arange(3) * 0.002, "qpos": np.zeros((3, 36)), "contact": np.ones((3, 2), bool)}
    meta = {"real_time_factor": math.nan, "pushes": [{"t": 1.0, "direction": (0.0, 1.0)}]}
    metrics = {"fell": fell, "speed_error_max": math.nan, "com_rms": {"walk": [np.float64(0.01), 0.0, 0.0]}}
    return SimResult(arrays, fell, 0.004 if fell else math.nan, "x touched the floor" if fell else "", meta, metrics)


@pytest.mark.parametrize("fell", [False, True])
def test_saved_file_holds_the_arrays_the_fall_and_strict_json_meta(tmp_path, fell):
    path = _result(fell).save(tmp_path / "run.npz")
    with np.load(path) as z:
        assert {"t", "qpos", "contact", "fell", "fall_time", "meta"} <= set(z.files)
        np.testing.assert_array_equal(z["contact"], np.ones((3, 2), bool))
        assert bool(z["fell"]) is fell
        assert float(z["fall_time"]) == (0.004 if fell else -1.0)
        meta = json.loads(str(z["meta"]), parse_constant=lambda c: pytest.fail(f"{c} in meta"))
    assert meta["real_time_factor"] is None and meta["metrics"]["speed_error_max"] is None
    assert meta["metrics"]["com_rms"]["walk"] == [0.01, 0.0, 0.0]
    assert meta["fall_reason"] == ("x touched the floor" if fell else "")


def test_other_suffixes_are_rejected_without_writing(tmp_path):
    with pytest.raises(InputError, match="npz"):
        _result(False).save(tmp_path / "run.json")
    assert list(tmp_path.iterdir()) == []
