"""Re-planning a TV-LIPM plan from a measured CoM state (paper 001 dynamics kept exactly).

Oracles: the plan's own reference before the re-plan (continuity), eq. (1) recomputed from the
returned arrays, and an independent numerical integration of eq. (1) (tests/physics.py).
"""

import numpy as np

import gaitshift
import physics
from gaitshift.planners.tvlip.replanner import Replanner


def test_replanning_keeps_position_velocity_and_zmp_continuous():
    sc = gaitshift.load_scenario("paper001-table2-walk-run-walk")
    traj = gaitshift.plan(sc)
    r = Replanner.from_scenario(sc)
    for t in (2.337, 4.05, 6.6, 9.0):  # mid single support, mid flight, others
        i = round(t / sc.dt)
        before = r.reference(traj.t[i])
        r.replan(traj.t[i], before[0][0, :2], before[1][0, :2])
        after = r.reference(traj.t[i])
        for x, y in zip(before[:2], after[:2], strict=True):
            np.testing.assert_allclose(x, y, atol=1e-9)
        if np.isfinite(before[3][0, 0]):
            np.testing.assert_allclose(before[3], after[3], atol=1e-9)  # the ZMP does not jump


def test_replanning_from_a_perturbed_state_keeps_exact_dynamics_and_stops_at_the_goal():
    sc = gaitshift.load_scenario("paper001-table2-walk-run-walk")
    traj = gaitshift.plan(sc)
    r = Replanner.from_scenario(sc)
    i = round(5.0 / sc.dt)
    r.replan(traj.t[i], traj.com_pos[i, :2] + [0.01, -0.01], traj.com_vel[i, :2] + [0.05, 0.05])
    t = traj.t[i:]
    p, v, a, c = r.reference(t)
    assert np.linalg.norm(p[0, :2] - (traj.com_pos[i, :2] + [0.01, -0.01])) < 1e-12
    sup = np.isfinite(c[:, 0])
    T = traj.stiffness[i:][sup][:, None]
    np.testing.assert_allclose(a[sup], (p[sup] - c[sup]) / T**2 - [0, 0, sc.gravity], atol=1e-6)
    goal = traj.footsteps[-2:, :3].mean(axis=0) + np.array([0.0, 0.0, sc.height])
    assert np.linalg.norm(p[-1] - goal) < 1e-3 and np.linalg.norm(v[-1]) < 1e-3
    d = {
        "t": t,
        "com_pos": p,
        "com_vel": v,
        "com_acc": a,
        "zmp": c,
        "phase": traj.phase[i:],
        "stiffness": traj.stiffness[i:],
        "boundary_t": traj.extras["boundary_t"],
    }
    within, across = physics.ode_errors(d, sc.gravity)
    assert within < 1e-6 and across < 1e-6
