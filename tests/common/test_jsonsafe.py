"""``finite_json``: numpy values become plain JSON and non-finite floats become null."""

from __future__ import annotations

import json
import math

import numpy as np

from gaitshift.common.jsonsafe import finite_json


def test_nested_numpy_values_become_strict_json():
    obj = {
        1: np.array([1.5, np.nan, np.inf]),
        "s": (np.int64(3), np.bool_(True), np.float32(0.25)),
        "n": [-math.inf, {"x": None, "y": "text"}],
    }
    out = finite_json(obj)
    text = json.dumps(out, allow_nan=False)
    assert json.loads(text) == {"1": [1.5, None, None], "s": [3, True, 0.25], "n": [None, {"x": None, "y": "text"}]}
    assert type(out["s"][0]) is int and type(out["s"][1]) is bool and type(out["s"][2]) is float
