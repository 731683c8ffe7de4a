"""The fixed horizons of a VHIP run: the unit responses solve eq. (13) of the running step, the
lateral oscillation puts the footholds exactly one step width apart, and the stop solver works on the
reversed stop horizon.

Oracles: the rows of eq. (9') evaluated here on the returned samples, and the footholds of a periodic
lateral gait from a dense solve of eq. (13) (numpy LU of the tridiagonal matrix built here).
"""

import numpy as np

import gaitshift
from gaitshift.planners.vhip.horizons import VhipHorizons
from gaitshift.trajectory.contract import LEFT, RIGHT


def _horizons():
    return VhipHorizons.from_scenario(gaitshift.load_scenario({"planner": "vhip", "dt": 0.004}))


def test_unit_responses_solve_the_running_step():
    h = _horizons()
    assert h.n_step == h.n_sup + h.n_fly == len(h.run_w) - 1
    w = h.run_w[1:-1]
    for resp, (v0, v1) in ((h.U, (1.0, 0.0)), (h.V, (0.0, 1.0))):
        rows = -resp[:-2] + (2 + w) * resp[1:-1] - resp[2:]  # eq. (9') with the ZMP at 0
        assert np.max(np.abs(rows)) < 1e-12
        np.testing.assert_allclose([(resp[1] - resp[0]) / h.dt, (resp[-1] - resp[-2]) / h.dt], [v0, v1], atol=1e-9)


def test_the_lateral_oscillation_puts_the_footholds_one_step_width_apart():
    """One step (flight, then a stance on the foot at y = 0) from take-off velocity ``u`` to ``-u``.
    In the periodic gait the next step is this one mirrored about the midline m; continuity of the CoM
    needs ``2 m - y(0) = y(end)``, and the next foot is at 2 m: the feet are ``2 |m|`` apart."""
    h = _horizons()
    n, dt = h.n_step, h.dt
    A = np.diag(2 + h.run_w) + np.diag(-np.ones(n), 1) + np.diag(-np.ones(n), -1)
    A[0, :2], A[n, -2:] = [-1.0, 1.0], [-1.0, 1.0]  # the velocity rows of eq. (12)
    u = h.u_left
    assert h.oscillation(LEFT) == u and h.oscillation(RIGHT) == -u
    rhs = np.zeros(n + 1)  # the ZMP at the foothold y = 0
    rhs[0], rhs[-1] = u * dt, -u * dt
    c = np.linalg.solve(A, rhs)
    midline = 0.5 * (c[0] + c[-1])
    assert abs(2 * abs(midline) - h.width) < 1e-9


def test_the_stop_solver_runs_on_the_reversed_stop_horizon():
    h = _horizons()
    np.testing.assert_array_equal(h.stop_solver.w, h.stop_w[::-1])
    np.testing.assert_array_equal(h.start_solver.w, h.start_w)
    assert len(h.stop_w) == h.n_fly + h.n_sup + h.n_stop + 1 and len(h.start_w) == h.n_start + h.n_sup + 1
