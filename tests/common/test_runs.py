"""``true_runs``: the maximal True runs of a mask, against a plain Python scan."""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from gaitshift.common.runs import true_runs


def _scan(mask):
    runs, start = [], None
    for i, v in enumerate(mask):
        if v and start is None:
            start = i
        if not v and start is not None:
            runs.append((start, i))
            start = None
    if start is not None:
        runs.append((start, len(mask)))
    return runs


@given(st.lists(st.booleans(), max_size=60))
def test_runs_match_a_python_scan(values):
    mask = np.array(values, bool)
    runs = true_runs(mask)
    assert runs == _scan(values)
    assert all(isinstance(a, int) and isinstance(b, int) for a, b in runs)


def test_edges_of_the_array_close_runs():
    assert true_runs(np.array([True, True, False, True])) == [(0, 2), (3, 4)]
    assert true_runs(np.zeros(5, bool)) == []
    assert true_runs(np.zeros(0, bool)) == []
