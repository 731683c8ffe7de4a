"""Re-solving the rest of a TV-LIPM plan on new footholds from a phase boundary (perceived terrain).

Oracles: the old plan at the boundary (continuity), Bellman's principle (the same footholds give the
same rest of the plan), eq. (1) of paper 001 recomputed from the samples, the definition of a swing in
the phase table, and the new footholds' heights (the CoM ends ``height`` above them).
"""

import numpy as np
import pytest

import gaitshift
import physics
from gaitshift.gait.footsteps import Footstep
from gaitshift.planners.tvlip.planner import ZMP_TOL, sequence_for, solve_boundaries
from gaitshift.planners.tvlip.resolve import lift_phase, resolve_from
from gaitshift.planners.tvlip.sampling import evaluate, sample
from gaitshift.trajectory.contract import FLIGHT


def _plan(name):
    sc = gaitshift.load_scenario(name)
    seq, _ = sequence_for(sc)
    bp = solve_boundaries(seq, sc.height, sc.gravity, sc.foot.size, sc.foot.zmp_margin, sc.foot.zmp_z)
    return sc, seq, bp


def _resolve(sc, seq, bp, k, feet):
    return resolve_from(seq, bp, k, feet, sc.height, sc.gravity, sc.foot.size, sc.foot.zmp_margin, sc.foot.zmp_z)


def _raised(seq, k, dz):
    """The footholds whose swings start two steps after boundary k or later raised by dz (a tread seen
    ahead: a tread seen at the last instant cannot be reached with the ZMP on the soles)."""
    lift = lift_phase(seq)
    return [
        Footstep(f.x, f.y, f.z + (dz if lift[j] >= k + 4 else 0.0), f.yaw, f.side) for j, f in enumerate(seq.footsteps)
    ]


@pytest.mark.parametrize("name", ["g1-walk", "paper001-table2-walk-run-walk"])
def test_lift_phase_is_the_first_phase_of_the_swing_onto_each_footstep(name):
    _, seq, _ = _plan(name)
    on, lift = seq.on, lift_phase(seq)
    assert (lift[:2] == -1).all()
    for j in range(2, len(seq.footsteps)):
        side = int(seq.footstep_side[j])
        k = lift[j]
        first_on = int(np.argmax(on[:, side] == j))
        assert on[k - 1, side] >= 0 and on[k - 1, side] != j  # on the previous footstep before
        assert (on[k:first_on, side] != j).all() and first_on > k  # then in the air until it lands on j
        assert (on[k:first_on, side] == -1).all() or seq.kind[k] == FLIGHT or (on[k:first_on, side] < 0).all()


@pytest.mark.parametrize("name", ["g1-walk", "paper001-table2-walk-run-walk"])
def test_the_same_footholds_give_the_same_rest_of_the_plan(name):
    sc, seq, bp = _plan(name)
    for k in (3, len(seq.phases) // 2):
        _, new = _resolve(sc, seq, bp, k, list(seq.footsteps))
        np.testing.assert_allclose(new.p, bp.p, atol=1e-7)
        np.testing.assert_allclose(new.v, bp.v, atol=1e-7)


@pytest.mark.parametrize("name", ["g1-walk", "paper001-table2-walk-run-walk"])
def test_raised_footholds_keep_the_state_continuous_and_eq1_exact_and_lift_the_com(name):
    sc, seq, bp = _plan(name)
    k = 5
    new_seq, new = _resolve(sc, seq, bp, k, _raised(seq, k, 0.08))
    assert new.violation <= 5 * ZMP_TOL  # a tread 8 cm higher two steps ahead: the soles hold the ZMP within 5 mm
    tk = seq.boundary_times[k]
    ref = [np.asarray(x) for x in evaluate(seq, bp, np.array([k]), np.array([0.0]), sc.gravity)]
    got = [np.asarray(x) for x in evaluate(new_seq, new, np.array([k]), np.array([0.0]), sc.gravity)]
    for a, b in zip(ref[:2], got[:2], strict=True):
        np.testing.assert_allclose(a, b, atol=1e-9)  # position and velocity at t_k
    if seq.kind[k] != FLIGHT and seq.kind[k - 1] != FLIGHT:
        np.testing.assert_allclose(ref[3], got[3], atol=1e-9)  # the ZMP does not jump
    fs = new_seq.footstep_array
    np.testing.assert_allclose(new.p[-1, 2], fs[-2:, 2].mean() + sc.height, atol=1e-9)  # ends above the new soles
    assert new.p[-1, 2] > bp.p[-1, 2] + 0.07
    d = sample(new_seq, new, sc.gravity, sc.dt, sc.swing_height)
    d["boundary_t"] = new_seq.boundary_times
    after = d["t"] >= tk
    sup = after & (d["phase"] != FLIGHT)
    T = d["stiffness"][sup][:, None]
    np.testing.assert_allclose(
        d["com_acc"][sup], (d["com_pos"][sup] - d["zmp"][sup]) / T**2 - [0, 0, sc.gravity], atol=1e-6
    )
    within, across = physics.ode_errors(d, sc.gravity)
    assert within < 1e-6 and across < 1e-6
