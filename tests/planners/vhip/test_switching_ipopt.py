"""The IPOPT reference (paper 003 solves State Switching 1 with IPOPT) and our solver reach the same
optimum of the same start problem.

Oracles: an independent dense solve of eq. (13) for the CoM of each returned ZMP, the support polygon
bounds, and the two solvers against each other.
"""

from __future__ import annotations

import numpy as np
from switching_cases import DT, N_DS, dense_com, start_problem

from gaitshift.planners.vhip.switching import solve_switching
from gaitshift.planners.vhip.switching_ipopt import solve_switching_ipopt


def test_ours_and_ipopt_solve_the_same_problem():
    prob = start_problem()
    ours, ref = solve_switching(prob), solve_switching_ipopt(prob)
    for sol in (ours, ref):
        p = np.vstack([sol.zmp, np.repeat(prob.y1[None], len(prob.w) - N_DS - 1, 0)])
        c = dense_com(prob.w, p, np.zeros(2), prob.v_end, DT)
        np.testing.assert_allclose(c[0], prob.c0, atol=1e-7)
        assert np.all(sol.zmp >= prob.lo - 1e-9) and np.all(sol.zmp <= prob.hi + 1e-9)
    # same optimum of the smoothness objective (ours scans dT1 on a 2 ms grid)
    np.testing.assert_allclose(ours.J, ref.J, rtol=1e-3, atol=1e-9)
    np.testing.assert_allclose(ours.dT1, ref.dT1, atol=0.01)
