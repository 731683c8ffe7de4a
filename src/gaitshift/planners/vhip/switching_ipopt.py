"""IPOPT reference for the start and stop problem of paper 003 (§3.2, eqs. (15)-(18)).

The paper solves State Switching 1 and 3 with IPOPT; :class:`IpoptSwitching` poses the very same
problem as our solver (:mod:`gaitshift.planners.vhip.switching`: the segmented cubic ZMP of eq. (16)
with the smoothness objective) for IPOPT through casadi, the optional extra ``gaitshift[ipopt]``
(imported lazily). ``gaitshift bench --only vhip.switching`` compares both; the tests check that they
reach the same optimum.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gaitshift.errors import InfeasibleError
from gaitshift.models.arrays import FloatArray
from gaitshift.models.tridiagonal import Horizon
from gaitshift.planners.vhip.switching import (
    MIN_SEGMENT,
    SwitchingProblem,
    SwitchingSolution,
    com_of,
    smoothness,
    zmp_samples_xy,
)

__all__ = ["IpoptSwitching", "solve_switching_ipopt"]


class IpoptSwitching:
    """The same start problem for IPOPT through casadi (optional dependency, imported lazily).

    Build once per horizon shape (weights, n_ds, dt) — like the paper's online use — then call
    :meth:`solve` with the boundary values. Variables per axis: (dT1, dT2, y_m, y'_m) (eq. (16)),
    constraints (16d), c_0 = c0 through eq. (13), and the ZMP bounds (16g) at every sample.
    """

    def __init__(self, w: FloatArray, n_ds: int, dt: float):
        try:
            import casadi as ca
        except ImportError as exc:  # pragma: no cover - depends on the installation
            raise InfeasibleError("IPOPT needs casadi: pip install 'gaitshift[ipopt]'") from exc
        self.n_ds, self.dt = n_ds, dt
        self.T = n_ds * dt
        probe = SwitchingProblem(
            np.asarray(w, float), n_ds, dt, np.zeros(2), np.zeros(2), np.zeros(2), np.zeros(2), np.zeros(2), np.zeros(2)
        )
        self.horizon = Horizon(probe.w, dt)
        g, _ = probe.affine_constraint(self.horizon)
        t = np.arange(n_ds + 1) * dt
        x = ca.SX.sym("x", 8)  # per axis k: dT1, dT2, ym, ydm at 4k..4k+3
        par = ca.SX.sym("par", 8)  # per axis k: y0, y1, R0 (= c0 - K), unused
        J: Any = 0  # casadi expressions (casadi has no type information)
        cons: list[Any] = []
        for k in range(2):
            h1, h2, ym, ydm = x[4 * k], x[4 * k + 1], x[4 * k + 2], x[4 * k + 3]
            y0, y1, R0 = par[4 * k], par[4 * k + 1], par[4 * k + 2]
            # eq. (18) (corrected b_2) for both segments, eqs. (16b)-(16c)
            b1: list[Any] = [y0, 0, (3 * (ym - y0) - ydm * h1) / h1**2, (2 * (y0 - ym) + ydm * h1) / h1**3]
            b2: list[Any] = [ym, ydm, (3 * (y1 - ym) - 2 * ydm * h2) / h2**2, (2 * (ym - y1) + ydm * h2) / h2**3]
            ps = []
            for ti in t:
                tau2 = ti - h1
                seg1 = b1[0] + ti * (b1[1] + ti * (b1[2] + ti * b1[3]))
                seg2 = b2[0] + tau2 * (b2[1] + tau2 * (b2[2] + tau2 * b2[3]))
                ps.append(ca.if_else(ti <= h1, seg1, seg2))
            p = ca.vertcat(*ps)
            cons += [h1 + h2, ca.dot(ca.DM(g), p) - R0, p]  # (16d), (16e)-(16f), (16g)
            # smoothness: integral of (2 b2 + 6 b3 t)^2 over [0, h] = 4 b2^2 h + 12 b2 b3 h^2 + 12 b3^2 h^3
            for b, h in ((b1, h1), (b2, h2)):
                J += 4 * b[2] ** 2 * h + 12 * b[2] * b[3] * h**2 + 12 * b[3] ** 2 * h**3
        self.solver = ca.nlpsol(
            "switching",
            "ipopt",
            {"x": x, "p": par, "f": J, "g": ca.vertcat(*cons)},
            {
                "ipopt.print_level": 0,
                "ipopt.sb": "yes",
                "print_time": 0,
                "ipopt.tol": 1e-10,
                "ipopt.constr_viol_tol": 1e-10,
            },
        )
        self._np = n_ds + 1

    def solve(self, prob: SwitchingProblem) -> SwitchingSolution:
        """Solve ``prob`` (same horizon as the constructor) from the initial guess dT1 = dT2 = T/2,
        y_m = (y0 + y1)/2, y'_m = 0."""
        _, K = prob.affine_constraint(self.horizon)
        T, hmin = self.T, MIN_SEGMENT * self.T
        x0, lbx, ubx, par, lbg, ubg = [], [], [], [], [], []
        for k in range(2):
            y0, y1 = float(prob.y0[k]), float(prob.y1[k])
            x0 += [T / 2, T / 2, 0.5 * (y0 + y1), 0.0]
            lbx += [hmin, hmin, -np.inf, -np.inf]
            ubx += [T - hmin, T - hmin, np.inf, np.inf]
            par += [y0, y1, float(prob.c0[k] - K[k]), 0.0]
            lbg += [T, 0.0] + [float(prob.lo[k])] * self._np
            ubg += [T, 0.0] + [float(prob.hi[k])] * self._np
        out = self.solver(x0=x0, lbx=lbx, ubx=ubx, p=par, lbg=lbg, ubg=ubg)
        if not self.solver.stats()["success"]:
            raise InfeasibleError(f"IPOPT failed on the start/stop problem: {self.solver.stats()['return_status']}")
        x = np.asarray(out["x"]).ravel()
        dT1, ym, ydm = x[[0, 4]], x[[2, 6]], x[[3, 7]]
        t = np.arange(self.n_ds + 1, dtype=np.float64) * self.dt
        zmp = zmp_samples_xy(t, dT1, T, np.asarray(prob.y0, float), ym, ydm, np.asarray(prob.y1, float))
        J = np.array([smoothness(dT1[k], T - dT1[k], prob.y0[k], ym[k], ydm[k], prob.y1[k]) for k in range(2)])
        return SwitchingSolution(
            dT1, ym, ydm, J, zmp, com_of(prob, zmp, self.horizon), int(self.solver.stats()["iter_count"])
        )


_IPOPT_CACHE: dict[tuple[bytes, int, float], IpoptSwitching] = {}


def solve_switching_ipopt(prob: SwitchingProblem) -> SwitchingSolution:
    """Solve ``prob`` with IPOPT (the paper's reference); the casadi solver is built once per horizon."""
    key = (prob.w.tobytes(), prob.n_ds, prob.dt)
    if key not in _IPOPT_CACHE:
        _IPOPT_CACHE.clear()
        _IPOPT_CACHE[key] = IpoptSwitching(prob.w, prob.n_ds, prob.dt)
    return _IPOPT_CACHE[key].solve(prob)
