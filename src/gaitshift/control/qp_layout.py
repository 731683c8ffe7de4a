"""The fixed structure of the whole-body QP for one set of stance feet, built once and refilled each tick.

Unknowns ``x = [qdd (nv), f (3k)]`` (k contact points of the stance soles). The QP is held in daqp's
two-sided form ``bl <= [x; A x] <= bu`` (the first n entries of ``bl``/``bu`` bound x itself), with
the rows of A in this order (:attr:`QpLayout.rows`):

* ``torque``: ``-tau_max - h_a <= M_a qdd - J_a^T f <= tau_max - h_a`` (nu rows; one two-sided row per
  motor instead of two one-sided rows);
* ``friction``: ``|f_x|, |f_y| <= mu f_z`` per point (4k rows, constant);
* ``cap``: per-foot ``sum f_z <= F_max`` (one row per stance foot, constant);
* ``dynamics``: the floating-base rows of ``M qdd + h = S^T tau + Jc^T f`` (6 equalities);
* ``feet``: non-sliding stance soles ``J_foot qdd = -Jdot_foot qd - K_v v_foot`` (6 equalities each).

Only the torque, dynamics and feet rows (and the bounds) change from tick to tick; the friction and
cap rows are written here once per (stance set, friction coefficient).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from gaitshift.control.qp_terms import INF, friction_rows


@dataclass
class QpLayout:
    """Index layout and constant rows of the QP for the stance feet ``stance`` (see module docstring).

    Attributes:
        stance: stance feet (0 left, 1 right), in order; nv, nu: dofs and motors; k: contact points;
        n: unknowns nv + 3k; rows: slices of A per block; A (m, n); bu, bl (n + m,); n_eq: equality
        rows (the last ones); gram_f: (3k, 3k) ``S^T S`` of the sum of the point forces ``S = [I I ... I]``
        (3, 3k); mu: friction coefficient.
    """

    stance: tuple[int, ...]
    nv: int
    nu: int
    k: int
    n: int
    rows: dict[str, slice]
    A: np.ndarray
    bu: np.ndarray
    bl: np.ndarray
    n_eq: int
    gram_f: np.ndarray
    mu: float

    @classmethod
    def build(cls, stance: tuple[int, ...], n_points: list[int], nv: int, nu: int, mu: float) -> QpLayout:
        """The layout of ``stance`` for soles of ``n_points`` contact points each, friction ``mu``."""
        k = sum(n_points[s] for s in stance)
        n, ns = nv + 3 * k, len(stance)
        sizes = {"torque": nu, "friction": 4 * k, "cap": ns, "dynamics": 6, "feet": 6 * ns}
        rows, start = {}, 0
        for name, size in sizes.items():
            rows[name] = slice(start, start + size)
            start += size
        A = np.zeros((start, n))
        A[rows["friction"]] = friction_rows(n, k, nv, mu)
        col = nv
        for j, s in enumerate(stance):
            A[rows["cap"].start + j, col + 2 : col + 3 * n_points[s] : 3] = 1.0
            col += 3 * n_points[s]
        bu = np.full(n + start, INF)
        bl = np.full(n + start, -INF)
        bl[nv + 2 : n : 3] = 0.0  # unilateral: f_z >= 0
        bu[n + rows["friction"].start : n + rows["friction"].stop] = 0.0
        gram_f = np.tile(np.eye(3), (k, k))
        return cls(tuple(stance), nv, nu, k, n, rows, A, bu, bl, 6 + 6 * ns, gram_f, mu)

    def bounds(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        """Views (upper, lower) of ``bu``/``bl`` on the rows of block ``name`` ("x": the unknowns)."""
        if name == "x":
            return self.bu[: self.n], self.bl[: self.n]
        r = self.rows[name]
        return self.bu[self.n + r.start : self.n + r.stop], self.bl[self.n + r.start : self.n + r.stop]
