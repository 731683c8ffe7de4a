"""External pushes: placement at mid single support and the per-tick force they apply.

The single-support phases are found with the independent segment finder of :mod:`physics`; the force
profile is integrated here (sum f dt) and must give each push's impulse exactly.
"""

from __future__ import annotations

import numpy as np
import pytest

import gaitshift
from gaitshift.sim.pushes import Push, mid_stance_pushes, push_forces
from physics import SS, segments


def test_pushes_are_centred_at_mid_single_support_of_the_chosen_steps_alternating_sides():
    traj = gaitshift.plan("g1-walk")
    ss = [(a, b) for a, b in segments(traj.phase) if traj.phase[a] == SS]
    pushes = mid_stance_pushes(traj, 12.0, steps=(2, 3, 99), duration=0.08)
    assert len(pushes) == 2  # step 99 is beyond the plan
    for push, k, side in zip(pushes, (2, 3), (1.0, -1.0), strict=True):
        a, b = ss[k - 1]
        assert push.t + push.duration / 2 == pytest.approx(0.5 * (traj.t[a] + traj.t[b]), abs=1e-12)
        assert push.direction == (0.0, side)
        assert push.impulse == 12.0 and push.duration == 0.08


def test_force_profile_delivers_each_impulse_from_its_start_tick():
    dt, settle = 0.002, 0.5
    pushes = (Push(t=1.0, impulse=10.0, duration=0.1, direction=(3.0, 4.0)), Push(t=2.0, impulse=5.0, duration=0.0))
    f = push_forces(pushes, settle, dt, 2000)
    first, second = f[: round(2.2 / dt)], f[round(2.2 / dt) :]
    np.testing.assert_allclose(first.sum(axis=0) * dt, [6.0, 8.0, 0.0], atol=1e-12)  # along (3, 4) / 5
    np.testing.assert_allclose(second.sum(axis=0) * dt, [0.0, 5.0, 0.0], atol=1e-12)  # default +y
    on = np.flatnonzero(np.any(f != 0.0, axis=1))
    assert on[0] == round((1.0 + settle) / dt) and on[49] == on[0] + 49  # 0.1 s = 50 ticks
    assert np.count_nonzero(np.any(second != 0.0, axis=1)) == 1  # a zero duration still lasts one tick


def test_a_push_beyond_the_run_is_cut_at_its_end():
    f = push_forces((Push(t=0.95, impulse=10.0, duration=0.1),), 0.0, 0.01, 100)
    assert np.count_nonzero(f[:, 1]) == 5
