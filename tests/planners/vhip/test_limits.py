"""The command limits: per-step change, sustainable speed, and the stride window of the foothold
that a take-off velocity implies (foothold = K - v V_0, Algorithm 1 in closed form).

Oracles: the limits re-derived by hand from the scenario numbers; the implied foothold recomputed
from the returned velocity.
"""

import numpy as np
import pytest

from gaitshift.planners.vhip.limits import clamp_by_strides, clip_change, speed_limit, stride_window


def test_changes_within_the_limit_pass_unchanged_and_larger_ones_are_clamped():
    last, dv = np.array([0.3, 0.0]), np.array([0.3, 0.1])
    np.testing.assert_array_equal(clip_change(np.array([0.6, -0.1]), last, dv), [0.6, -0.1])
    np.testing.assert_array_equal(clip_change(np.array([0.6 + 1e-13, 0.05]), last, dv), [0.6 + 1e-13, 0.05])
    np.testing.assert_allclose(clip_change(np.array([1.2, -0.5]), last, dv), [0.6, -0.1])


def test_speed_limit_is_the_smaller_of_max_speed_and_the_steady_stride():
    # T = 0.4 s, stride 0.9 m: x 2.25 m/s; y: min(0.2 - 0.12, 0.9 - 0.2) / 0.4 = 0.2 m/s
    vmax, why = speed_limit(np.array([1.5, 0.4]), 0.9, 0.4, 0.2, 0.12)
    np.testing.assert_allclose(vmax, [1.5, 0.2])
    assert why == ["limits.max_speed", "steady strides within limits"]


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_stride_clamp_keeps_the_implied_foothold_in_the_window(sign):
    lo, hi = stride_window(sign, 0.4, 0.12)
    assert (lo[1], hi[1]) == ((0.12, 0.4) if sign > 0 else (-0.4, -0.12))
    K, V0 = np.array([0.9, 0.3 * sign]), -0.35
    for v in (np.array([0.0, 0.0]), np.array([3.0, -2.0]), np.array([-3.0, 2.0])):
        out = clamp_by_strides(v, K, V0, lo, hi, v, np.array([10.0, 10.0]))  # no per-step limit
        step = K - out * V0
        assert np.all(step >= lo - 1e-9) and np.all(step <= hi + 1e-9)
        inside = np.all(K - v * V0 >= lo) and np.all(K - v * V0 <= hi)
        assert np.array_equal(out, v) == bool(inside)


def test_stride_clamp_never_changes_the_velocity_by_more_than_the_per_step_limit():
    lo, hi = stride_window(1.0, 0.4, 0.12)
    K, V0, last = np.array([0.9, 0.3]), -0.35, np.array([0.5, 0.1])
    out = clamp_by_strides(np.array([3.0, 2.0]), K, V0, lo, hi, last, np.array([0.3, 0.1]))
    # x: the window needs v <= (0.4 - 0.9) / 0.35 = -1.43, the per-step limit allows >= 0.2: the stride
    # gives; y: the window allows v <= (0.4 - 0.3) / 0.35 = 0.286, the per-step limit <= 0.2
    np.testing.assert_allclose(out, [0.2, 0.2])
