"""Windows of a plan (gaitshift.trajectory.window): a window is indexed by absolute time, eq. (1), as the
whole plan is; cuts of a plan put end to end give the plan back, array for array and boundary for
boundary; a window far into a run keeps its step exact."""

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import gaitshift
from gaitshift.trajectory.contract import Trajectory
from gaitshift.trajectory.window import cut, first_index, index_at, join, window


@pytest.fixture(scope="module")
def traj():
    sc = gaitshift.load_scenario(
        {"gait": [{"gait": "walk", "steps": 2}, {"gait": "run", "steps": 3}, {"gait": "walk", "steps": 2}], "dt": 0.01}
    )
    return gaitshift.plan(sc)


def _same(a: Trajectory, b: Trajectory) -> None:
    x, y = a.arrays(), b.arrays()
    assert x.keys() == y.keys()
    for k in x:
        np.testing.assert_array_equal(x[k], y[k], err_msg=k)


@settings(max_examples=40, deadline=None)
@given(start=st.integers(0, 10_000), t=st.floats(-1.0, 100.0))
def test_a_window_is_indexed_by_absolute_time_like_the_whole_plan(traj, start, t):
    w = window(traj, start)
    first = first_index(w)
    assert first == min(start, len(traj) - 2) and w.t[0] == traj.t[first]
    i, j = index_at(w, t), index_at(traj, t)
    if t >= w.t[0]:  # inside the window (or past both ends): the same sample
        np.testing.assert_array_equal(w.com_pos[i], traj.com_pos[j])
        assert w.t[i] == traj.t[j]
    else:  # before the window: its first sample
        assert i == 0


@settings(max_examples=40, deadline=None)
@given(splits=st.lists(st.integers(0, 400), max_size=6))
def test_cuts_put_end_to_end_give_the_plan_back(traj, splits):
    """Any split points, pieces of zero or one sample included (two plans adopted at one tick)."""
    bounds = sorted(min(s, len(traj)) for s in splits)
    starts = [0, *bounds]
    cuts = [cut(traj, a, b) for a, b in itertools.pairwise(starts)]
    _same(join(cuts, traj, starts[-1]), traj)


def test_a_window_keeps_only_the_boundaries_inside_it(traj):
    w = window(traj, 40, 120)
    bt = traj.extras["boundary_t"]
    inside = bt[(bt >= traj.t[40]) & (bt <= traj.t[119])]
    np.testing.assert_array_equal(w.extras["boundary_t"], inside)
    assert len(w) == 80 and w.t[0] == traj.t[40]


def test_a_window_far_into_a_run_keeps_its_step_exact(traj):
    """At t = 600 s, ``t[1] - t[0]`` is off the step by ~1e-13 s; the planner's own step is the window's."""
    data = traj.arrays() | {"t": traj.t + 600.0}
    far = Trajectory.from_arrays(data, traj.meta)
    assert far.t[1] - far.t[0] != traj.meta["dt"]
    assert far.dt == traj.meta["dt"] == traj.dt
    assert first_index(far) == round(600.0 / traj.meta["dt"])
    assert index_at(far, 600.0 + 7 * traj.dt) == 7
    bad = Trajectory.from_arrays(traj.arrays(), traj.meta | {"dt": 2 * traj.dt})  # a meta that disagrees
    assert bad.dt == pytest.approx(traj.t[1] - traj.t[0], abs=0)
