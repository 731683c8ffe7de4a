"""The start problem of the online-planner tests (paper 003 §3.2) and an independent dense eq. (13)
solve (numpy's dense LU of the tridiagonal matrix built here), shared by test_switching*.py."""

from __future__ import annotations

import numpy as np

import gaitshift
from gaitshift.models.tridiagonal import tridiagonal_system
from gaitshift.models.vhip import VerticalGait, row_weights, stance_profiles
from gaitshift.planners.vhip.switching import SwitchingProblem

G, DT, N_DS, N_SUP, N_FLY = 9.81, 0.004, 300, 70, 30


def vertical() -> VerticalGait:
    sc = gaitshift.load_scenario("paper003-variable-speed")
    return stance_profiles(sc.heights, G, N_SUP * DT, N_FLY * DT)


def start_problem(v_end=(0.3, -0.2), y1=(0.0, 0.1)):
    z, _, zdd = vertical().start_horizon(DT, N_DS, N_SUP)
    w = row_weights(z, zdd, G, DT)
    return SwitchingProblem(
        w,
        N_DS,
        DT,
        np.zeros(2),
        np.array(y1),
        np.zeros(2),
        np.array(v_end),
        np.array([-0.1, -0.15]),
        np.array([0.1, 0.15]),
    )


def dense_com(w, p, v0, v1, dt):
    lo, di, up = tridiagonal_system(w)
    A = np.diag(di) + np.diag(up, 1) + np.diag(lo, -1)
    rhs = w[:, None] * p
    rhs[0], rhs[-1] = np.asarray(v0) * dt, np.asarray(v1) * dt
    return np.linalg.solve(A, rhs)
