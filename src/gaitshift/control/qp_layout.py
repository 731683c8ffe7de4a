"""The fixed structure of the whole-body QP for one set of stance feet, built once and refilled each tick.

Unknowns ``x = [qdd (nv), f (3k)]`` (k contact points of the stance soles). The QP is held in daqp's
two-sided form ``bl <= [x; A x] <= bu`` (the first n entries of ``bl``/``bu`` bound x itself), with
the rows of A in this order (:attr:`QpLayout.rows`):

* ``dynamics``: the floating-base rows of ``M qdd + h = S^T tau + Jc^T f`` (6 equalities);
* ``torque``: ``-tau_max - h_a <= M_a qdd - J_a^T f <= tau_max - h_a`` (nu rows; one two-sided row per
  motor instead of two one-sided rows). With these two blocks adjacent, their rows are
  ``[M, -Jc^T]`` taken at the dofs (base, actuated): one copy per tick;
* ``feet``: non-sliding stance soles ``J_foot qdd = -Jdot_foot qd - K_v v_foot`` (6 equalities each);
* ``friction``: ``|f_x|, |f_y| <= mu f_z`` per point (4k rows, constant);
* ``cap``: per-foot ``sum f_z <= F_max`` (one row per stance foot).

Only the dynamics, torque and feet rows (and the bounds) change from tick to tick; the friction and
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
        n: unknowns nv + 3k; rows: slices of A per block; A (m, n); bu, bl (n + m,); sense: daqp's
        constraint kinds (n + m,), 5 on the equality rows; up, lo: views of bu, bl per block ("x": the
        unknowns, "dynamics+torque": both blocks); feet: the slice of side indices of the stance soles;
        gram_f: (3k, 3k) ``S^T S`` of the sum of the point forces ``S = [I I ... I]`` (3, 3k); mu: friction coefficient.
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
    sense: np.ndarray
    up: dict[str, np.ndarray]
    lo: dict[str, np.ndarray]
    feet: slice
    gram_f: np.ndarray
    mu: float

    @classmethod
    def build(cls, stance: tuple[int, ...], n_points: list[int], nv: int, nu: int, mu: float) -> QpLayout:
        """The layout of ``stance`` for soles of ``n_points`` contact points each, friction ``mu``."""
        k = sum(n_points[s] for s in stance)
        n, ns = nv + 3 * k, len(stance)
        sizes = {"dynamics": 6, "torque": nu, "feet": 6 * ns, "friction": 4 * k, "cap": ns}
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
        sense = np.zeros(n + start, dtype=np.intc)
        shifted = {"x": slice(0, n)} | {key: slice(n + r.start, n + r.stop) for key, r in rows.items()}
        shifted["dynamics+torque"] = slice(n, n + rows["torque"].stop)
        for name in ("dynamics", "feet"):
            sense[shifted[name]] = 5  # daqp: equality (active and immutable)
        up = {key: bu[r] for key, r in shifted.items()}
        lo = {key: bl[r] for key, r in shifted.items()}
        up["friction"][:] = 0.0
        gram_f = np.tile(np.eye(3), (k, k))
        feet = slice(stance[0], stance[-1] + 1) if stance else slice(0, 0)
        return cls(tuple(stance), nv, nu, k, n, rows, A, bu, bl, sense, up, lo, feet, gram_f, mu)
