"""The vectorised sampling of a TV-LIPM plan equals the per-sample closed forms to rounding.

Oracle: the reference path kept in the benchmark suite (:func:`gaitshift.bench.tvlip.reference_sample`:
``support_state`` / ``flight_state`` of eqs. (1)-(6) and ``swing_path`` evaluated sample by sample,
the planner's sampling before issue 10), and ``np.searchsorted`` for the phase of each sample. The
bound is 1e-12 relative to each array's largest value (measured: about 1e-15).
"""

import numpy as np
import pytest

import gaitshift
from gaitshift.bench.tvlip import reference_evaluate, reference_sample
from gaitshift.planners.tvlip.planner import sequence_for, solve_boundaries
from gaitshift.planners.tvlip.sampling import evaluate, phase_samples, sample

TURNING_STAIRS = {
    "gait": [{"gait": "walk", "steps": 3}, {"gait": "run", "steps": 4}, {"gait": "walk", "steps": 3}],
    "foot": {"zmp_z": [-0.05, 0.05]},
    "profile": {"max_stride": 0.3, "step_height": 0.05, "yaw_rate": 0.1, "accelerate_steps": 2, "decelerate_steps": 2},
}


def _plan(name):
    sc = gaitshift.load_scenario(name)
    seq, _ = sequence_for(sc)
    bp = solve_boundaries(seq, sc.height, sc.gravity, sc.foot.size, sc.foot.zmp_margin, sc.foot.zmp_z)
    return sc, seq, bp


def assert_close_relative(new, ref, key, rel=1e-12):
    """Same NaN pattern, and |new - ref| <= rel * max |ref| over the finite entries."""
    assert new.shape == ref.shape and new.dtype == ref.dtype, key
    if ref.dtype.kind != "f":
        np.testing.assert_array_equal(new, ref, err_msg=key)
        return
    finite = np.isfinite(ref)
    np.testing.assert_array_equal(np.isfinite(new), finite, err_msg=key)
    if finite.any():
        scale = np.max(np.abs(ref[finite]))
        assert np.max(np.abs(new[finite] - ref[finite])) <= rel * scale, key


@pytest.mark.parametrize("name", ["paper001-table2-walk-run-walk", "paper001-table1-running", "turning-stairs"])
def test_vectorised_sampling_equals_the_per_sample_closed_forms(name):
    sc, seq, bp = _plan(TURNING_STAIRS if name == "turning-stairs" else name)
    new = sample(seq, bp, sc.gravity, sc.dt, sc.swing_height)
    ref = reference_sample(seq, bp, sc.gravity, sc.dt, sc.swing_height)
    assert new.keys() == ref.keys()
    for key in ref:
        assert_close_relative(new[key], ref[key], key)
    for key in ("com_pos", "com_vel", "com_acc", "zmp", "foot_pos"):
        assert new[key].flags.c_contiguous, key


def test_each_sample_lies_in_the_phase_searchsorted_finds():
    """A sample within 1e-9 dt of a boundary starts the new phase; the last sample stays in the last."""
    _, seq, _ = _plan("paper001-table2-walk-run-walk")
    tb = seq.boundary_times
    for dt in (0.001, 0.004, 0.0033):
        ps = phase_samples(tb, dt)
        t = np.arange(len(ps.t)) * dt
        k = np.clip(np.searchsorted(tb, t + 1e-9 * dt, side="right") - 1, 0, len(tb) - 2)
        np.testing.assert_array_equal(ps.t, t)
        np.testing.assert_array_equal(ps.k, k)
        np.testing.assert_array_equal(ps.s, np.maximum(t - tb[k], 0.0))
        assert ps.t[-1] <= tb[-1] + 1e-9 * dt < ps.t[-1] + dt


def test_evaluate_at_arbitrary_times_equals_the_per_sample_closed_forms():
    """Samples in any order (as the re-planner queries them), phases gathered by index."""
    sc, seq, bp = _plan("paper001-table2-walk-run-walk")
    rng = np.random.default_rng(3)
    k = rng.integers(0, len(seq.phases), 500)
    s = rng.uniform(0.0, 1.0, 500) * seq.duration[k]
    new, ref = evaluate(seq, bp, k, s, sc.gravity), reference_evaluate(seq, bp, k, s, sc.gravity)
    for a, b, key in zip(new, ref, "pvac", strict=True):
        assert_close_relative(a, b, key)
