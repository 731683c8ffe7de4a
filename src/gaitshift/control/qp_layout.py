"""The fixed structure of the whole-body QP for one set of stance feet, built once and refilled each tick
(:class:`QpLayout`), and the gain-dependent terms the controller keeps with it (:class:`StanceTerms`).

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
  rotation (refilled per tick through :attr:`QpLayout.cone`).
The per-foot cap ``F_z <= F_max`` (the touchdown/lift-off force ramp) is an upper bound on the
unknown ``F_z`` itself (:attr:`QpLayout.cap`).

The cost matrix H and vector f are held here too (block diagonal: the qdd block and the wrench block
are rewritten whole every tick, the rest stays zero), with the views the controller writes through:
the qdd block's diagonal and the wrench-task rows ``T_w`` (6 + 6 ns, 6 ns)::

    T_w = [[I,      0, I,      0],      sum of the forces
           [[d_0]x, I, [d_1]x, I],      moment about the CoM (d_s = sole centre - CoM)
           [L^T B_0^T,  0        ],      regularisation, Q = L L^T (per sole)
           [0,  L^T B_1^T        ]]

whose ``[d_s]x`` blocks (:attr:`QpLayout.skew`) and regularisation blocks (:attr:`QpLayout.reg`)
change each tick; the wrench block of H is ``T_w^T W T_w``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.lib.stride_tricks import as_strided

from gaitshift.control.qp_terms import INF
from gaitshift.control.wrench_cone import SoleCone


def _blocks(
    a: np.ndarray, row: int, col: int, shape: tuple[int, ...], steps: tuple[tuple[int, int], ...]
) -> np.ndarray:
    """A writable view of the 2-D (C order) array ``a`` from ``a[row, col]``: ``shape`` with the
    strides of ``steps`` given as (rows, columns) pairs."""
    s0, s1 = a.strides
    base = a[row:, col:]
    return as_strided(base, shape, tuple(r * s0 + c * s1 for r, c in steps))


@dataclass
class QpLayout:
    """Index layout, constant rows and work buffers of the QP for the stance feet ``stance``.

    Attributes:
        stance: stance feet (0 left, 1 right), in order; nv, nu: dofs and motors; n: unknowns nv + 6 ns;
        rows: slices of A per block; A (m, n); A_torque: the torque rows of A; bu, bl (n + m,); sense:
        daqp's constraint kinds (n + m,), 5 on the equality rows; up, lo: views of bu, bl per block
        ("x": the unknowns, "dynamics+torque": both blocks); feet: slice of the stance sides; cap:
        indices of the F_z unknowns; cones: the stance soles' :class:`SoleCone`; cone: the
        (m, 6 ns) view of the cone rows of A on the wrenches (``C B^T``, C block diagonal); H (n, n),
        f (n,): the cost; H_diag: the (nv,) diagonal of the qdd block; Tw: the wrench-task rows;
        skew: their (ns, 3, 3) ``[d_s]x`` blocks; reg: the (6 ns, 6 ns) regularisation rows
        ``L^T B^T`` of Tw; B (6 ns, 6 ns): ``diag(R_s^T, R_s^T, ...)`` over the stance soles;
        B_blocks: its (ns, 2, 3, 3) diagonal blocks; mu: friction coefficient.
    """

    stance: tuple[int, ...]
    nv: int
    nu: int
    n: int
    rows: dict[str, slice]
    A: np.ndarray
    A_torque: np.ndarray
    bu: np.ndarray
    bl: np.ndarray
    sense: np.ndarray
    up: dict[str, np.ndarray]
    lo: dict[str, np.ndarray]
    feet: slice
    cap: np.ndarray
    cones: tuple[SoleCone, ...]
    cone: np.ndarray
    H: np.ndarray
    f: np.ndarray
    H_diag: np.ndarray
    Tw: np.ndarray
    skew: np.ndarray
    reg: np.ndarray
    B: np.ndarray
    B_blocks: np.ndarray
    mu: float

    @classmethod
    def build(cls, stance: tuple[int, ...], cones: tuple[SoleCone, SoleCone], nv: int, nu: int) -> QpLayout:
        """The layout of ``stance`` for the soles' wrench ``cones`` (left, right)."""
        ns = len(stance)
        cs = tuple(cones[s] for s in stance)
        n = nv + 6 * ns
        sizes = {"dynamics": 6, "torque": nu, "feet": 6 * ns, "cone": sum(len(c.faces) for c in cs)}
        rows, start = {}, 0
        for name, size in sizes.items():
            rows[name] = slice(start, start + size)
            start += size
        A = np.zeros((start, n))
        Tw = np.zeros((6 + 6 * ns, 6 * ns))
        for j in range(ns):
            Tw[:3, 6 * j : 6 * j + 3] = Tw[3:6, 6 * j + 3 : 6 * j + 6] = np.eye(3)
        B = np.zeros((6 * ns, 6 * ns))
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
        return cls(
            stance=tuple(stance),
            nv=nv,
            nu=nu,
            n=n,
            rows=rows,
            A=A,
            A_torque=A[rows["torque"]],
            bu=bu,
            bl=bl,
            sense=sense,
            up=up,
            lo=lo,
            feet=slice(stance[0], stance[-1] + 1) if stance else slice(0, 0),
            cap=nv + 6 * np.arange(ns) + 2,
            cones=cs,
            cone=A[rows["cone"], nv:],
            H=H,
            f=np.zeros(n),
            H_diag=as_strided(H, (nv,), (H.strides[0] + H.strides[1],)),
            Tw=Tw,
            skew=_blocks(Tw, 3, 0, (ns, 3, 3), ((0, 6), (1, 0), (0, 1))),
            reg=Tw[6:],
            B=B,
            B_blocks=_blocks(B, 0, 0, (ns, 2, 3, 3), ((6, 6), (3, 3), (1, 0), (0, 1))),
            mu=cones[0].mu,
        )


class StanceTerms:
    """What one stance set (left, right in stance) fixes for the current gains: the QP layout, the
    frame-task rows in use among the 24 (position and orientation of the swing soles, orientation of
    the torso and the pelvis) and their weights, the swing sides, the stance soles' cone faces and
    regularisation rows ``L^T`` (``Q = L L^T``), block diagonal over the stance soles, (m, 6 ns) and
    (6 ns, 6 ns), in the sole frames (times ``B^T`` in the world, :attr:`QpLayout.B`), and the
    weights of the wrench-task rows (CoM, angular momentum, regularisation)."""

    def __init__(self, lay: QpLayout, key: tuple[bool, bool], w_task: np.ndarray, w_cent: np.ndarray, w_reg: float):
        self.lay = lay
        self.swing = tuple(s for s in (0, 1) if not key[s])
        self.rows = np.array([r for s in self.swing for r in range(6 * s, 6 * s + 6)] + [15, 16, 17, 21, 22, 23])
        self.w_rows = w_task.ravel()[self.rows]
        ns = len(lay.stance)
        self.faces = np.zeros((lay.rows["cone"].stop - lay.rows["cone"].start, 6 * ns))
        self.reg = np.zeros((6 * ns, 6 * ns))
        r = 0
        for j, c in enumerate(lay.cones):
            self.faces[r : r + len(c.faces), 6 * j : 6 * j + 6] = c.faces
            self.reg[6 * j : 6 * j + 6, 6 * j : 6 * j + 6] = np.linalg.cholesky(c.metric).T
            r += len(c.faces)
        self.w_wrench = np.concatenate([w_cent, np.full(6 * len(lay.stance), w_reg)])
