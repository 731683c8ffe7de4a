"""Every built-in TV-LIPM scenario satisfies the physics at every sample (paper 001 §II).

Checks use tests/physics.py, which re-derives everything from the file's arrays.
"""

import numpy as np
import pytest

import gaitshift

import physics

SCENARIOS = ["paper001-table1-running", "paper001-table2-running", "paper001-table2-walk-run-walk"]


@pytest.fixture(scope="module", params=SCENARIOS)
def planned(request, tmp_path_factory):
    sc = gaitshift.load_scenario(request.param)
    path = tmp_path_factory.mktemp("plans") / f"{request.param}.npz"
    gaitshift.plan(sc).save(path)
    with np.load(path) as z:
        d = {k: z[k] for k in z.files}
    return sc, d


def test_eq1_holds_at_every_support_sample(planned):
    sc, d = planned
    assert physics.eq1_error(d, sc.gravity) < 1e-6


def test_flight_is_ballistic(planned):
    sc, d = planned
    assert physics.flight_error(d, sc.gravity) < 1e-9


def test_eq1_holds_under_independent_numerical_integration(planned):
    sc, d = planned
    within, _ = physics.ode_errors(d, sc.gravity)
    assert within < 1e-6


def test_velocity_and_acceleration_match_finite_differences(planned):
    _, d = planned
    ev, ea, ea2 = physics.finite_difference_errors(d)
    assert ev < 1e-4 and ea < 1e-3 and ea2 < 1e-3


def test_com_is_continuous_across_phase_switches(planned):
    sc, d = planned
    _, across = physics.ode_errors(d, sc.gravity)
    assert across < 1e-6  # position and velocity carried across every switch by the ODE


def test_zmp_stays_inside_the_support_polygon(planned):
    sc, d = planned
    assert physics.zmp_outside_polygon(d, sc.foot.size) < 1e-3


def test_running_segments_have_real_flight(planned):
    sc, d = planned
    segs = [(a, b) for a, b in physics.segments(d["phase"]) if d["phase"][a] == physics.F]
    n_run = sum(s.steps for s in sc.gait if s.gait == "run")
    assert len(segs) == n_run
    dt = d["t"][1] - d["t"][0]
    for a, b in segs:
        assert not d["contact"][a:b].any()
        assert (b - a) * dt == pytest.approx(sc.timing.flight, abs=1.5 * dt)
        assert np.all(d["foot_pos"][a + 1:b, :, 2] > 0.0)  # both soles off the ground after take-off
        assert np.all(np.isnan(d["zmp"][a:b]))


def test_running_touchdown_and_takeoff_heights_equal_h(planned):
    sc, d = planned
    bp = d["boundary_com_pos"]
    kinds = d["phase_kind"]
    fl = np.flatnonzero(kinds == physics.F)
    # at both ends of every flight the CoM is at the nominal height above the flat ground
    np.testing.assert_allclose(bp[fl, 2], sc.height, atol=1e-9)
    np.testing.assert_allclose(bp[fl + 1, 2], sc.height, atol=1e-9)


def test_plan_ends_at_rest_at_the_goal(planned):
    sc, d = planned
    goal = d["footsteps"][-2:, :3].mean(axis=0) + [0, 0, sc.height]
    assert np.linalg.norm(d["com_vel"][-1]) < 1e-3
    assert np.linalg.norm(d["com_pos"][-1] - goal) < 1e-3
    assert np.linalg.norm(d["com_vel"][0]) < 1e-12


def test_feet_in_contact_do_not_move(planned):
    _, d = planned
    c = d["contact"]
    for s in (0, 1):
        stay = c[1:, s] & c[:-1, s]
        assert np.max(np.abs(np.diff(d["foot_pos"][:, s], axis=0)[stay])) < 1e-12


def test_file_has_no_nan_outside_the_documented_places(planned):
    _, d = planned
    for key in ("t", "com_pos", "com_vel", "com_acc", "foot_pos", "footsteps"):
        assert np.all(np.isfinite(d[key])), key
    sup = d["phase"] != physics.F
    assert np.all(np.isfinite(d["zmp"][sup])) and np.all(np.isfinite(d["stiffness"][sup]))


def test_stairs_and_turning_plan_satisfy_the_same_physics():
    sc = gaitshift.load_scenario({"gait": [{"gait": "walk", "steps": 6}], "foot": {"zmp_z": [-0.05, 0.05]},
                                  "profile": {"max_stride": 0.3, "step_height": 0.05, "yaw_rate": 0.1,
                                              "accelerate_steps": 2, "decelerate_steps": 2}})
    d = gaitshift.plan(sc).arrays()
    assert physics.eq1_error(d, sc.gravity) < 1e-6
    assert max(physics.ode_errors(d, sc.gravity)) < 1e-6
    assert d["footsteps"][-1, 2] == pytest.approx(0.30)
    goal = d["footsteps"][-2:, :3].mean(axis=0) + [0, 0, sc.height]
    assert np.linalg.norm(d["com_pos"][-1] - goal) < 1e-3 and np.linalg.norm(d["com_vel"][-1]) < 1e-3


def test_banded_solution_equals_a_dense_kkt_solve():
    """The O(K) banded solve returns the same boundary ZMPs as a dense least-squares solve of the
    same problem built here from eqs. (3)-(6) by hand (a short walk, no active bounds)."""
    sc = gaitshift.load_scenario({"gait": [{"gait": "walk", "steps": 2}],
                                  "profile": {"max_stride": 0.1, "accelerate_steps": 0, "decelerate_steps": 0}})
    tr = gaitshift.plan(sc)
    e = tr.extras
    bt, kinds, Ts = e["boundary_t"], e["phase_kind"], e["phase_stiffness"]
    tau = np.diff(bt)
    K = len(tau)
    # unknowns: c_0..c_K (x only); states follow from eqs. (3)-(4) from rest; the end must be at rest
    # at the goal -> linear equality constraints M c = r; minimise |c - c_ref|^2.
    def propagate(cx):
        p, v = e["boundary_com_pos"][0, 0], 0.0
        for k in range(K):
            T, s = Ts[k], tau[k]
            cd = (cx[k + 1] - cx[k]) / s
            e0, ed = p - cx[k], v - cd
            p, v = (cx[k + 1] + e0 * np.cosh(s / T) + T * ed * np.sinh(s / T),
                    cd + e0 / T * np.sinh(s / T) + ed * np.cosh(s / T))
        return np.array([p, v])
    base = propagate(np.zeros(K + 1))
    M = np.column_stack([propagate(np.eye(K + 1)[j]) - base for j in range(K + 1)])
    goal = tr.footsteps[-2:, 0].mean()
    r = np.array([goal, 0.0]) - base
    # regularisation targets (eq. (7) box origins), from the file's contacts and feet: the sole of an
    # adjacent single support, else the mid-point of both soles
    def foot_x_mid_phase(k):
        i = int(np.searchsorted(tr.t, (bt[k] + bt[k + 1]) / 2))
        return tr.foot_pos[i, tr.contact[i], 0].mean()
    ref = np.array([foot_x_mid_phase(k) for k in
                    [next((j for j in (b - 1, b) if 0 <= j < K and kinds[j] == 1), min(b, K - 1))
                     for b in range(K + 1)]])
    KKT = np.block([[np.eye(K + 1), M.T], [M, np.zeros((2, 2))]])
    sol = np.linalg.solve(KKT, np.r_[ref, r])
    np.testing.assert_allclose(sol[:K + 1], e["boundary_zmp"][:, 0], atol=1e-9)


def test_replanning_keeps_position_velocity_and_zmp_continuous():
    from gaitshift.planners.tvlip import Replanner

    sc = gaitshift.load_scenario("paper001-table2-walk-run-walk")
    traj = gaitshift.plan(sc)
    r = Replanner.from_scenario(sc)
    for t in (2.337, 4.05, 6.6, 9.0):  # mid single support, mid flight, others
        i = int(round(t / sc.dt))
        before = r.reference(traj.t[i])
        r.replan(traj.t[i], before[0][0, :2], before[1][0, :2])
        after = r.reference(traj.t[i])
        for x, y in zip(before[:2], after[:2]):
            np.testing.assert_allclose(x, y, atol=1e-9)
        if np.isfinite(before[3][0, 0]):
            np.testing.assert_allclose(before[3], after[3], atol=1e-9)  # the ZMP does not jump


def test_replanning_from_a_perturbed_state_keeps_exact_dynamics_and_stops_at_the_goal():
    from gaitshift.planners.tvlip import Replanner

    sc = gaitshift.load_scenario("paper001-table2-walk-run-walk")
    traj = gaitshift.plan(sc)
    r = Replanner.from_scenario(sc)
    i = int(round(5.0 / sc.dt))
    r.replan(traj.t[i], traj.com_pos[i, :2] + [0.01, -0.01], traj.com_vel[i, :2] + [0.05, 0.05])
    t = traj.t[i:]
    p, v, a, c = r.reference(t)
    assert np.linalg.norm(p[0, :2] - (traj.com_pos[i, :2] + [0.01, -0.01])) < 1e-12
    sup = np.isfinite(c[:, 0])
    T = traj.stiffness[i:][sup][:, None]
    np.testing.assert_allclose(a[sup], (p[sup] - c[sup]) / T**2 - [0, 0, sc.gravity], atol=1e-6)
    goal = traj.footsteps[-2:, :3].mean(axis=0) + [0, 0, sc.height]
    assert np.linalg.norm(p[-1] - goal) < 1e-3 and np.linalg.norm(v[-1]) < 1e-3
    d = {"t": t, "com_pos": p, "com_vel": v, "com_acc": a, "zmp": c, "phase": traj.phase[i:],
         "stiffness": traj.stiffness[i:], "boundary_t": traj.extras["boundary_t"]}
    within, across = physics.ode_errors(d, sc.gravity)
    assert within < 1e-6 and across < 1e-6
