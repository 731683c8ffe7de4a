"""The banded KKT boundary solve of paper 001 §II-B returns the least-squares optimum of the exact
dynamics (eqs. (3)-(6)) and equals a dense solve of the same system.

Oracles: a dense equality-constrained least-squares problem built here from eqs. (3)-(4) by hand
(propagating the closed forms with numpy cosh/sinh), and a dense LU of the same KKT matrix.
"""

import numpy as np

import gaitshift
from gaitshift.planners.tvlip.planner import sequence_for, solve_boundaries


def test_banded_solution_equals_a_dense_kkt_solve():
    """The O(K) banded solve returns the same boundary ZMPs as a dense least-squares solve of the
    same problem built here from eqs. (3)-(6) by hand (a short walk, no active bounds)."""
    sc = gaitshift.load_scenario(
        {
            "gait": [{"gait": "walk", "steps": 2}],
            "profile": {"max_stride": 0.1, "accelerate_steps": 0, "decelerate_steps": 0},
        }
    )
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
            p, v = (
                cx[k + 1] + e0 * np.cosh(s / T) + T * ed * np.sinh(s / T),
                cd + e0 / T * np.sinh(s / T) + ed * np.cosh(s / T),
            )
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

    ref = np.array(
        [
            foot_x_mid_phase(k)
            for k in [
                next((j for j in (b - 1, b) if 0 <= j < K and kinds[j] == 1), min(b, K - 1)) for b in range(K + 1)
            ]
        ]
    )
    KKT = np.block([[np.eye(K + 1), M.T], [M, np.zeros((2, 2))]])
    sol = np.linalg.solve(KKT, np.r_[ref, r])
    np.testing.assert_allclose(sol[: K + 1], e["boundary_zmp"][:, 0], atol=1e-9)


def test_banded_and_dense_lu_give_the_same_boundary_plan():
    """The banded LU (gbsv) and a dense LU of the same KKT matrix agree to rounding on the 20-step
    walk-run-walk (active hinge constraints included)."""
    sc = gaitshift.load_scenario("paper001-table2-walk-run-walk")
    seq, _ = sequence_for(sc)
    args = (sc.height, sc.gravity, sc.foot.size, sc.foot.zmp_margin, sc.foot.zmp_z)
    banded, dense = solve_boundaries(seq, *args), solve_boundaries(seq, *args, dense=True)
    for a, b in ((banded.p, dense.p), (banded.v, dense.v), (banded.c, dense.c)):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-9)
    assert banded.iterations == dense.iterations
    assert banded.violation < 1e-3
