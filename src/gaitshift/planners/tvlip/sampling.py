"""Closed-form sampling of a TV-LIPM plan (paper 001, eqs. (1)-(6)): CoM, ZMP and the swing feet.

Per phase k the closed forms are gathered once into coefficient rows (:class:`PhaseTable`), then
evaluated for all samples at once (one ``exp`` per sample). In support, with ``E = exp(s / T)``,
``e0 = p0 - c0 - g T^2 e_z``, ``cd = (c1 - c0) / tau`` and ``ed = v0 - cd``, eqs. (3)-(4) read

    c(s) = c0 + cd s
    p(s) = c(s) + g T^2 e_z + A E + B / E        A = (e0 + T ed) / 2,  B = (e0 - T ed) / 2
    v(s) = cd + (A E - B / E) / T
    a(s) = (A E + B / E) / T^2                   (= (p - c) / T^2 - g e_z, eq. (1))

since ``cosh = (E + 1/E) / 2`` and ``sinh = (E - 1/E) / 2``. In flight (eqs. (5)-(6)) the same rows
hold the take-off state (A = B = 0, 1/T = 0) and the ballistic term ``-g s^2 / 2`` is added to z.
The swing feet are gathered the same way: per phase and side the lift-off sole, the step to the
touchdown sole and the height sextic in the normalised swing time u (a sole in contact is a swing of
zero length, u = 0). This replaces the per-sample evaluation of
:func:`gaitshift.models.tvlip.support_state` and :func:`gaitshift.gait.swing.swing_path`; both
paths agree to rounding: at most 1.3e-15 of each array's largest value on the built-in TV-LIPM
scenarios (``gaitshift bench --only tvlip`` keeps the old path as its baseline, and the tests compare
them to 1e-12). The float outputs of :func:`sample` share one allocation (fewer fresh pages per plan).

Shapes: N samples, K phases; positions m, velocities m/s, accelerations m/s^2, times s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from gaitshift.gait.sequence import GaitSequence
from gaitshift.gait.swing import EdgeClearance
from gaitshift.models.arrays import BoolArray, FloatArray, IntArray
from gaitshift.models.sextic import SEXTIC_INVERSE
from gaitshift.planners.tvlip.kkt import BoundaryPlan
from gaitshift.trajectory.contract import FLIGHT, LEFT, RIGHT

__all__ = [
    "PhaseSamples",
    "PhaseTable",
    "SwingTable",
    "com_samples",
    "evaluate",
    "feet",
    "phase_samples",
    "phase_table",
    "sample",
    "swing_table",
]


@dataclass(frozen=True)
class PhaseSamples:
    """Which phase each sample belongs to and how far into it.

    Attributes:
        t: (N,) sample times, s.
        s: (N,) time since the start of the sample's phase, s (>= 0).
        k: (N,) phase index of each sample.
        counts: (K,) samples per phase when the samples are sorted by phase (one run per phase),
            else None (then rows are gathered through ``k``).
    """

    t: FloatArray
    s: FloatArray
    k: IntArray
    counts: IntArray | None

    def expand(self, rows: FloatArray) -> FloatArray:
        """Per-phase values (K,) -> per-sample values (N,)."""
        if self.counts is not None:
            return np.repeat(rows, self.counts)
        return np.take(rows, self.k)


def phase_samples(boundary_times: FloatArray, dt: float) -> PhaseSamples:
    """Samples every ``dt`` from 0 to the last boundary. A sample within 1e-9 dt of a boundary starts
    the new phase (the sample after the last boundary, if any, stays in the last phase)."""
    tb = boundary_times
    K = len(tb) - 1
    n = math.floor(tb[-1] / dt + 1e-9) + 1
    t = np.arange(n) * dt
    # phase j >= 1 starts at the first sample with t + 1e-9 dt >= tb[j] (t is sorted: O(K log n))
    first = np.searchsorted(t + 1e-9 * dt, tb[1:K], side="left")
    counts = np.diff(np.concatenate([[0], first, [n]]))
    s = np.repeat(tb[:K], counts)
    np.subtract(t, s, out=s)
    np.maximum(s, 0.0, out=s)
    return PhaseSamples(t, s, np.repeat(np.arange(K), counts), counts)


@dataclass(frozen=True)
class PhaseTable:
    """Per-phase coefficients of the closed forms (see module doc), rows of length K.

    Attributes:
        inv_T: 1/T in support, 0 in flight, 1/s.
        base: (3, K) ZMP c0 in support, take-off CoM p0 in flight, m.
        rate: (3, K) ZMP rate cd in support, take-off velocity v0 in flight, m/s.
        A, B: (3, K) weights of exp(s/T) and exp(-s/T) in the CoM position, m (0 in flight).
        offset: (K,) g T^2 in support (z only), 0 in flight, m.
        ballistic: (K,) the vertical acceleration of flight, -g, in flight; 0 in support, m/s^2.
        zmp_mask: (K,) 0 in support, NaN in flight (added to the ZMP).
    """

    inv_T: FloatArray
    base: FloatArray
    rate: FloatArray
    A: FloatArray
    B: FloatArray
    offset: FloatArray
    ballistic: FloatArray
    zmp_mask: FloatArray


def phase_table(seq: GaitSequence, bp: BoundaryPlan, g: float) -> PhaseTable:
    """The coefficient rows of every phase of ``seq`` for the boundary plan ``bp`` (gravity g)."""
    fl = seq.kind == FLIGHT
    sup = ~fl
    T = np.where(sup, seq.stiffness, 0.0)
    tau = seq.duration
    p0, v0, c0, c1 = bp.p[:-1].T, bp.v[:-1].T, bp.c[:-1].T, bp.c[1:].T
    cd = (c1 - c0) / tau
    gT2 = g * T**2
    e0 = p0 - c0
    e0[2] -= gT2
    Ted = T * (v0 - cd)
    inv_T = np.divide(1.0, T, out=np.zeros_like(T), where=sup)
    return PhaseTable(
        inv_T=inv_T,
        base=np.where(sup, c0, p0),
        rate=np.where(sup, cd, v0),
        A=np.where(sup, 0.5 * (e0 + Ted), 0.0),
        B=np.where(sup, 0.5 * (e0 - Ted), 0.0),
        offset=np.where(sup, gT2, 0.0),
        ballistic=np.where(sup, 0.0, -g),
        zmp_mask=np.where(sup, 0.0, np.nan),
    )


def evaluate(
    seq: GaitSequence, bp: BoundaryPlan, k: IntArray, s: FloatArray, g: float
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """CoM position, velocity, acceleration and ZMP, each (len(k), 3), at time ``s`` (s) into phase
    ``k``: eqs. (1)-(4) in support, (5)-(6) in flight (ZMP NaN). Any order of samples."""
    k = np.asarray(k, dtype=np.intp)
    s = np.asarray(s, float)
    return com_samples(phase_table(seq, bp, g), PhaseSamples(t=s, s=s, k=k, counts=None))  # t is not used


def com_samples(
    table: PhaseTable,
    ps: PhaseSamples,
    out: tuple[FloatArray, FloatArray, FloatArray, FloatArray] | None = None,
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """CoM position, velocity, acceleration and ZMP (each (N, 3)) of the samples ``ps`` (written into
    ``out`` when given); gravity is in the table's flight and offset rows."""
    n = len(ps.s)
    s = ps.s
    inv_T = ps.expand(table.inv_T)
    E = s * inv_T
    np.exp(E, out=E)
    Ei = np.divide(1.0, E)
    inv_T2 = inv_T * inv_T
    nan_mask = ps.expand(table.zmp_mask)
    pos, vel, acc, zmp = out if out is not None else tuple(np.empty((n, 3)) for _ in range(4))
    q, both = np.empty(n), np.empty(n)
    for j in range(3):
        rate = ps.expand(table.rate[j])
        np.multiply(rate, s, out=q)
        q += ps.expand(table.base[j])  # c(s) in support, p0 + v0 s in flight
        np.add(q, nan_mask, out=zmp[:, j])
        ae = ps.expand(table.A[j])
        ae *= E
        be = ps.expand(table.B[j])
        be *= Ei
        np.add(ae, be, out=both)
        ae -= be
        ae *= inv_T  # (A E - B / E) / T
        if j == 2:  # g T^2 in support; the ballistic terms -g, -g s, -g s^2 / 2 in flight
            q += ps.expand(table.offset)
            fall = ps.expand(table.ballistic)
            np.multiply(both, inv_T2, out=acc[:, j])
            acc[:, j] += fall
            fall *= s
            ae += fall
            fall *= s
            fall *= 0.5
            q += fall
        else:
            np.multiply(both, inv_T2, out=acc[:, j])
        np.add(ae, rate, out=vel[:, j])
        np.add(q, both, out=pos[:, j])
    return pos, vel, acc, zmp


@dataclass(frozen=True)
class SwingTable:
    """Per phase and side (arrays (K, 2, ...)): where the sole rests or lifts off, and its swing.

    Attributes:
        rest: (K, 2, 3) the footstep under the sole in contact, the lift-off footstep in a swing, m.
        swinging: (K, 2) bool, the sole is in the air during the phase.
        t_lift: (K, 2) lift-off time of the swing, s; inv_dur: (K, 2) 1 / swing duration, 1/s.
        step: (K, 2, 2) horizontal step from lift-off to touchdown, m (0 in contact).
        a36: (K, 2, 4) height sextic coefficients a_3..a_6 in the swing time u, m (0 in contact).
        w0, inv_w: (K, 2) start and 1 / length of the window of the horizontal blend in u
            (:class:`~gaitshift.gait.swing.EdgeClearance`; 0 and 1 without terrain).
    """

    rest: FloatArray
    swinging: BoolArray
    t_lift: FloatArray
    inv_dur: FloatArray
    step: FloatArray
    a36: FloatArray
    w0: FloatArray
    inv_w: FloatArray


def swing_table(
    seq: GaitSequence, swing_height: float, edges: EdgeClearance | None = None, kept: BoolArray | None = None
) -> SwingTable:
    """The swings of both feet per phase: from the footstep before (last contact) to the footstep after
    (next contact), the apex ``swing_height`` above the higher of the two (m); over terrain (``edges``)
    the horizontal blend runs in the window that clears its edges, except in the swings ``kept`` ((K, 2)
    bool per phase and side: a re-plan keeps their old samples)."""
    on = seq.on  # (K, 2)
    fs = seq.footstep_array
    tb = seq.boundary_times
    K = len(on)
    ks = np.arange(K)[:, None]
    last = np.maximum.accumulate(np.where(on >= 0, ks, -1), axis=0)
    nxt = np.minimum.accumulate(np.where(on >= 0, ks, K)[::-1], axis=0)[::-1]
    lift_k, land_k = np.maximum(last, 0), np.minimum(nxt, K - 1)
    sides = np.arange(2)[None, :]
    start = fs[on[lift_k, sides], :3]  # (K, 2, 3)
    end = fs[on[land_k, sides], :3]
    t_lift, t_land = tb[lift_k + 1], tb[land_k]
    sw = on < 0
    start[~sw] = fs[on[~sw], :3]  # in contact: rests on its footstep
    end[~sw] = start[~sw]  # a swing of zero length: no step, no sextic
    rise = end[..., 2] - start[..., 2]
    clearance = np.where(sw, np.maximum(start[..., 2], end[..., 2]) + swing_height - start[..., 2], 0.0)
    # a3..a6 = M^-1 [z1 - z0, 0, 0, apex - z0]
    a36 = rise[..., None] * SEXTIC_INVERSE[:, 0] + clearance[..., None] * SEXTIC_INVERSE[:, 3]
    inv_dur = np.divide(1.0, t_land - t_lift, out=np.zeros((K, 2)), where=sw)
    w0, inv_w = np.zeros((K, 2)), np.ones((K, 2))
    if edges is not None:
        for k, side in zip(*np.nonzero(sw if kept is None else sw & ~kept), strict=True):
            a, b = edges.window(start[k, side], end[k, side], swing_height)
            w0[k, side], inv_w[k, side] = a, 1.0 / (b - a)
    return SwingTable(start, sw, t_lift, inv_dur, end[..., :2] - start[..., :2], a36, w0, inv_w)


def feet(
    seq: GaitSequence,
    ps: PhaseSamples,
    swing_height: float,
    out: FloatArray | None = None,
    edges: EdgeClearance | None = None,
    kept: BoolArray | None = None,
) -> FloatArray:
    """Sole centres (N, 2, 3): fixed on their footstep in contact, swing paths in between (minimum-jerk
    horizontal blend and the height sextic through the apex ``swing_height`` above the higher sole,
    as :func:`gaitshift.gait.swing.swing_path`), written into ``out`` when given.

    One formula for all samples: a sole in contact is a swing of zero length (u = 0, no step, no
    sextic), so its position is its footstep exactly. Over terrain, see :func:`swing_table`."""
    tab = swing_table(seq, swing_height, edges, kept)
    n = len(ps.s)
    if out is None:
        out = np.empty((n, 2, 3))
    u, u3, blend, z = (np.empty(n) for _ in range(4))
    uh = np.empty(n)
    for side in (LEFT, RIGHT):
        np.subtract(ps.t, ps.expand(np.where(tab.swinging[:, side], tab.t_lift[:, side], 0.0)), out=u)
        u *= ps.expand(tab.inv_dur[:, side])
        np.clip(u, 0.0, 1.0, out=u)
        np.subtract(u, ps.expand(tab.w0[:, side]), out=uh)  # the horizontal blend's window
        uh *= ps.expand(tab.inv_w[:, side])
        np.clip(uh, 0.0, 1.0, out=uh)
        np.multiply(uh, uh, out=u3)
        u3 *= uh
        np.multiply(uh, 6.0, out=blend)  # minimum jerk: u^3 (10 + u (6 u - 15))
        blend -= 15.0
        blend *= uh
        blend += 10.0
        blend *= u3
        for j in range(2):
            x = ps.expand(tab.step[:, side, j])
            x *= blend
            np.add(x, ps.expand(tab.rest[:, side, j]), out=out[:, side, j])
        np.multiply(u, u, out=u3)
        u3 *= u
        a = tab.a36[:, side]  # (K, 4)
        np.multiply(ps.expand(a[:, 3]), u, out=z)
        for c in (2, 1):
            z += ps.expand(a[:, c])
            z *= u
        z += ps.expand(a[:, 0])
        z *= u3
        np.add(z, ps.expand(tab.rest[:, side, 2]), out=out[:, side, 2])
    return out


def sample(
    seq: GaitSequence,
    bp: BoundaryPlan,
    g: float,
    dt: float,
    swing_height: float,
    edges: EdgeClearance | None = None,
    kept: BoolArray | None = None,
) -> dict[str, FloatArray]:
    """Closed-form sampling of CoM, ZMP and feet at a fixed step ``dt`` (arrays of the contract); the
    swings clear the terrain's edges given by ``edges`` (except those ``kept``, :func:`swing_table`).

    The float arrays are C-contiguous views into one block (one allocation instead of ten)."""
    ps = phase_samples(seq.boundary_times, dt)
    counts = ps.counts
    assert counts is not None  # phase_samples sorts the samples by phase
    n = len(ps.t)
    sizes = [3 * n] * 4 + [6 * n, n, 2 * n]  # pos, vel, acc, zmp, feet, stiffness, command
    views = np.split(np.empty(sum(sizes)), np.cumsum(sizes)[:-1])
    pos, vel, acc, zmp = (v.reshape(n, 3) for v in views[:4])
    kinds = seq.kind
    sup = kinds != FLIGHT
    com_samples(phase_table(seq, bp, g), ps, out=(pos, vel, acc, zmp))
    foot_pos = views[4].reshape(n, 2, 3)
    feet(seq, ps, swing_height, out=foot_pos, edges=edges, kept=kept)
    stiffness = views[5]
    stiffness[:] = np.repeat(np.where(sup, seq.stiffness, np.nan), counts)
    command = views[6].reshape(n, 2)
    command.fill(np.nan)
    return {
        "t": ps.t,
        "com_pos": pos,
        "com_vel": vel,
        "com_acc": acc,
        "zmp": zmp,
        "phase": np.repeat(kinds, counts),
        "stiffness": stiffness,
        "command_vel": command,
        "contact": np.repeat(seq.on >= 0, counts, axis=0),
        "foot_pos": foot_pos,
    }
