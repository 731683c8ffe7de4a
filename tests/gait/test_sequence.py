"""Gait sequences: phase layout and stiffness assignment close the vertical motion (paper 001 Fig. 2)."""

import numpy as np
import pytest

import gaitshift
from gaitshift.errors import InputError
from gaitshift.gait.footsteps import stride_profile
from gaitshift.planners.tvlip.planner import sequence_for
from gaitshift.trajectory.contract import DS, FLIGHT, SS

K = gaitshift.stiffness(0.95, 0.4, 0.15, 0.15)


def seq_of(gait, **kw):
    return sequence_for(gaitshift.load_scenario({"gait": gait, **kw}))[0]


def test_stride_profile_is_the_paper_trapezoid():
    s = stride_profile(20, 0.5, 8, 8)
    assert s.max() == pytest.approx(0.5) and np.sum(np.isclose(s, 0.5)) == 4
    np.testing.assert_allclose(s, s[::-1])
    assert np.all(np.diff(s[:9]) > 0)


def test_walk_run_transition_uses_T_t0_then_T_t1():
    seq = seq_of([{"gait": "walk", "steps": 2}, {"gait": "run", "steps": 3}, {"gait": "walk", "steps": 2}])
    kinds, T = seq.kind, seq.stiffness
    first_f = int(np.flatnonzero(kinds == FLIGHT)[0])
    assert kinds[first_f - 1] == SS and T[first_f - 1] == K.T_t1
    assert kinds[first_f - 2] == DS and T[first_f - 2] == K.T_t0
    last_f = int(np.flatnonzero(kinds == FLIGHT)[-1])
    assert T[last_f + 1] == K.T_t1 and kinds[last_f + 2] == DS and T[last_f + 2] == K.T_t0
    between = T[(kinds == SS)][1:-1]
    assert np.sum(between == K.T_r) == 2  # SS between two flights
    assert np.all(np.isnan(T[kinds == FLIGHT]))


def test_running_from_standstill_inserts_the_transition_double_support():
    seq = seq_of([{"gait": "run", "steps": 3}])
    assert list(seq.kind[:4]) == [DS, DS, SS, FLIGHT]
    assert seq.stiffness[0] == K.T_w and seq.stiffness[1] == K.T_t0 and seq.stiffness[2] == K.T_t1


def test_a_single_walking_step_between_runs_is_rejected():
    with pytest.raises(InputError, match="gait"):
        seq_of([{"gait": "run", "steps": 2}, {"gait": "walk", "steps": 1}, {"gait": "run", "steps": 2}])


def test_feet_alternate_and_the_plan_closes_side_by_side():
    seq = seq_of([{"gait": "walk", "steps": 5}])
    side = seq.footstep_side
    assert list(side[:2]) == [0, 1] and np.all(np.diff(side[2:]) != 0)
    last, closing = seq.footstep_array[-2], seq.footstep_array[-1]
    assert last[0] == pytest.approx(closing[0]) and abs(last[1] - closing[1]) == pytest.approx(0.2)


def test_stride_beyond_reach_is_an_input_error():
    sc = gaitshift.load_scenario({"profile": {"max_stride": 1.5}})
    with pytest.raises(InputError, match="max_stride"):
        gaitshift.plan(sc)
