"""The fixed structure of the whole-body QP for one set of stance feet, built once and refilled each tick.

Unknowns ``x = [qdd (nv), w_s (6) per stance foot]``, ``w_s = [F_s; tau_s]`` the contact wrench of sole
s about its centre, world frame. The QP is held in daqp's two-sided form ``bl <= [x; A x] <= bu`` (the
first n entries of ``bl``/``bu`` bound x itself), with the rows of A in this order (:attr:`QpLayout.rows`):

* ``dynamics``: the floating-base rows of ``M qdd + h = S^T tau + sum_s J_s^T w_s`` (6 equalities);
* ``torque``: ``-tau_max - h_a <= M_a qdd - J_a^T w <= tau_max - h_a`` (nu rows; one two-sided row per
  motor). With these two blocks adjacent, their rows are ``[M, -J_feet^T]`` taken at the dofs (base,
  actuated): one copy per tick;
* ``feet``: non-sliding stance soles ``J_s qdd = -Jdot_s qd - K_v v_s`` (6 equalities each);
* ``cone``: the contact wrench cone of each stance sole, ``C_s B_s^T w_s <= 0`` with ``C_s`` its faces
  in the sole frame (:mod:`gaitshift.control.wrench_cone`) and ``B_s = diag(R_s, R_s)`` the sole
  rotation (refilled per tick through :attr:`QpLayout.cone`);
* ``cap``: per-foot ``F_z <= F_max`` (one constant row per stance foot).

The cost matrix H and vector f are held here too (block diagonal: the qdd block and the wrench block
are rewritten whole every tick, the rest stays zero), with the views the controller writes through:
the qdd block's diagonal, the per-foot (6, 6) blocks of the wrench block, and the centroidal map
``A_c`` (6, 6 ns) ``= [[I, 0, I, 0], [[d_s]x, I, ...]]`` (sum of forces; moment about the CoM,
``d_s`` = sole centre - CoM) with its ``[d_s]x`` blocks.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.lib.stride_tricks import as_strided

from gaitshift.control.qp_terms import INF
from gaitshift.control.wrench_cone import SoleCone


def _blocks(a: np.ndarray, count: int, rows: int, cols: int, step_r: int, step_c: int) -> np.ndarray:
    """A writable (count, rows, cols) view of ``a`` (2-D, C order): block i starts ``i step_r`` rows and
    ``i step_c`` columns after ``a[0, 0]``."""
    s0, s1 = a.strides
    return as_strided(a, (count, rows, cols), (step_r * s0 + step_c * s1, s0, s1))


@dataclass
class QpLayout:
    """Index layout, constant rows and work buffers of the QP for the stance feet ``stance``.

    Attributes:
        stance: stance feet (0 left, 1 right), in order; nv, nu: dofs and motors; n: unknowns nv + 6 ns;
        rows: slices of A per block; A (m, n); bu, bl (n + m,); sense: daqp's constraint kinds (n + m,),
        5 on the equality rows; up, lo: views of bu, bl per block ("x": the unknowns,
        "dynamics+torque": both blocks); feet: slice of the stance sides; cones: the stance soles'
        :class:`SoleCone`; cone: per stance foot, the (m_s, 2, 3) view of its cone rows of A on its wrench
        (``C B^T`` written as ``C.reshape(m_s, 2, 3) @ R^T``); H (n, n), f (n,): the cost;
        H_diag: the (nv,) diagonal of the qdd block; H_feet: the (6, 6) wrench blocks on the diagonal as
        (ns, 2, 2, 3, 3) (force/torque row block, column block, 3, 3);
        Ac (6, 6 ns): centroidal map; Ac_skew: its (ns, 3, 3) ``[d_s]x`` blocks; mu: friction coefficient.
    """

    stance: tuple[int, ...]
    nv: int
    nu: int
    n: int
    rows: dict[str, slice]
    A: np.ndarray
    bu: np.ndarray
    bl: np.ndarray
    sense: np.ndarray
    up: dict[str, np.ndarray]
    lo: dict[str, np.ndarray]
    feet: slice
    cones: tuple[SoleCone, ...]
    cone: list[np.ndarray]
    H: np.ndarray
    f: np.ndarray
    H_diag: np.ndarray
    H_feet: np.ndarray
    Ac: np.ndarray
    Ac_skew: np.ndarray
    mu: float

    @classmethod
    def build(cls, stance: tuple[int, ...], cones: tuple[SoleCone, SoleCone], nv: int, nu: int) -> QpLayout:
        """The layout of ``stance`` for the soles' wrench ``cones`` (left, right)."""
        ns = len(stance)
        cs = tuple(cones[s] for s in stance)
        n = nv + 6 * ns
        sizes = {"dynamics": 6, "torque": nu, "feet": 6 * ns, "cone": sum(len(c.faces) for c in cs), "cap": ns}
        rows, start = {}, 0
        for name, size in sizes.items():
            rows[name] = slice(start, start + size)
            start += size
        A = np.zeros((start, n))
        cone, r0 = [], rows["cone"].start
        for j, c in enumerate(cs):
            m = len(c.faces)
            cone.append(as_strided(A[r0:, nv + 6 * j :], (m, 2, 3), (A.strides[0], 3 * A.strides[1], A.strides[1])))
            r0 += m
            A[rows["cap"].start + j, nv + 6 * j + 2] = 1.0
        bu = np.full(n + start, INF)
        bl = np.full(n + start, -INF)
        sense = np.zeros(n + start, dtype=np.intc)
        shifted = {"x": slice(0, n)} | {key: slice(n + r.start, n + r.stop) for key, r in rows.items()}
        shifted["dynamics+torque"] = slice(n, n + rows["torque"].stop)
        for name in ("dynamics", "feet"):
            sense[shifted[name]] = 5  # daqp: equality (active and immutable)
        up = {key: bu[r] for key, r in shifted.items()}
        lo = {key: bl[r] for key, r in shifted.items()}
        up["cone"][:] = 0.0
        H = np.zeros((n, n))
        Ac = np.zeros((6, 6 * ns))
        for j in range(ns):
            Ac[:3, 6 * j : 6 * j + 3] = Ac[3:, 6 * j + 3 : 6 * j + 6] = np.eye(3)
        feet = slice(stance[0], stance[-1] + 1) if stance else slice(0, 0)
        return cls(
            stance=tuple(stance),
            nv=nv,
            nu=nu,
            n=n,
            rows=rows,
            A=A,
            bu=bu,
            bl=bl,
            sense=sense,
            up=up,
            lo=lo,
            feet=feet,
            cones=cs,
            cone=cone,
            H=H,
            f=np.zeros(n),
            H_diag=as_strided(H, (nv,), (H.strides[0] + H.strides[1],)),
            H_feet=_blocks(H[nv:, nv:], ns, 6, 6, 6, 6).reshape(ns, 2, 3, 2, 3).transpose(0, 1, 3, 2, 4),
            Ac=Ac,
            Ac_skew=_blocks(Ac[3:], ns, 3, 3, 0, 6),
            mu=cones[0].mu,
        )
