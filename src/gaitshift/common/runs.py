"""Runs of a boolean mask: the maximal intervals where it is True."""

from __future__ import annotations

import numpy as np


def true_runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """``[start, stop)`` index pairs of the maximal runs of True in a boolean array ``mask`` (N,).

    ``mask[start:stop]`` is all True, and ``mask[start - 1]`` / ``mask[stop]`` are False or outside
    the array. Pairs are in increasing order; an all-False mask gives ``[]``.
    """
    edges = np.diff(np.concatenate([[False], np.asarray(mask, bool), [False]]).astype(np.int8))
    starts = np.flatnonzero(edges == 1)
    stops = np.flatnonzero(edges == -1)
    return [(int(a), int(b)) for a, b in zip(starts, stops, strict=True)]
