"""A background re-planner's plans, waited for and compared bit for bit with the inline ones (tests/control)."""

from __future__ import annotations

import time
from dataclasses import fields

import numpy as np


def same(x, y):
    """Equal values, recursively through dataclasses, dicts, lists and tuples; arrays bit for bit (NaN
    equal to NaN: a flight's ZMP)."""
    if hasattr(x, "__dataclass_fields__"):
        return type(x) is type(y) and all(same(getattr(x, f.name), getattr(y, f.name)) for f in fields(x))
    if isinstance(x, dict):
        return x.keys() == y.keys() and all(same(x[k], y[k]) for k in x)
    if isinstance(x, list | tuple):
        return len(x) == len(y) and all(same(u, v) for u, v in zip(x, y, strict=True))
    if isinstance(x, np.ndarray):
        return x.dtype == y.dtype and np.array_equal(x, y, equal_nan=x.dtype.kind == "f")
    return x == y or (x != x and y != y)


def assert_same(a, b):
    """Every field of two dataclasses (Trajectory, PlanSamples) equal (:func:`same`)."""
    for f in fields(a):
        assert same(getattr(a, f.name), getattr(b, f.name)), f.name


def wait_for(rp, n, timeout=120.0):
    """The updates a background re-planner finishes, until ``n`` (or the timeout: the test then fails)."""
    got, end = [], time.monotonic() + timeout
    while len(got) < n and time.monotonic() < end:
        got += rp.take()
        time.sleep(0.01)
    return got
