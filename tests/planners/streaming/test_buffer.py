"""The plan buffer keeps global sample indices across sliding and growing, never drops a sample that
was not released, and stores each column with its shape and dtype.

Oracle: a plain Python dict from sample index to value, written alongside.
"""

import numpy as np

from gaitshift.planners.streaming.buffer import SampleBuffer


def test_global_indices_survive_sliding_and_growing():
    buf = SampleBuffer({"x": ((2,), np.float64), "flag": ((), np.bool_)}, capacity=16)
    ref: dict[int, float] = {}
    rng = np.random.default_rng(5)
    start, read = 0, 0
    for _ in range(500):
        m = int(rng.integers(1, 12))
        vals = rng.normal(size=m)
        buf.write(start, x=np.column_stack([vals, -vals]), flag=vals > 0)
        ref.update({start + j: float(vals[j]) for j in range(m)})
        start += m
        read = max(read, start - int(rng.integers(0, 20)))  # the consumer lags behind the planner
        buf.release(read)
        for i in range(max(read, buf.base), start):  # everything not released is still there
            assert buf["x"][i][0] == ref[i] and buf["x"][i][1] == -ref[i]
            assert bool(buf["flag"][i]) == (ref[i] > 0)
    assert buf.n == start
    assert buf.base > 0  # old rows were dropped
    assert len(buf.arrays["x"]) < start  # and the storage did not grow with the run
    assert buf.arrays["flag"].dtype == np.bool_ and buf.arrays["x"].shape[1:] == (2,)


def test_overwriting_planned_samples_replaces_them():
    buf = SampleBuffer({"x": ((), np.float64)}, capacity=8)
    buf.write(0, x=np.arange(6.0))
    buf.write(3, x=np.array([30.0, 40.0, 50.0, 60.0]))
    np.testing.assert_array_equal(buf["x"][0:7], [0, 1, 2, 30, 40, 50, 60])
    buf["x"][1:3] = [10.0, 20.0]
    assert buf.n == 7 and buf["x"][2] == 20.0
