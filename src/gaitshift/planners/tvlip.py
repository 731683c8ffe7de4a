"""TV-LIPM planner of paper 001 §II-B: CoM and ZMP over given footsteps.

Decision variables are the CoM position p_k, velocity v_k and ZMP c_k at every phase boundary
k = 0..K. The problem

    min  1/2 sum_k ( w_r^2 |c_k - c_ref,k|^2 + w_h^2 |hinge_k(c_k)|^2 )
    s.t. (p_k+1, v_k+1) = Phi_k(p_k, v_k, c_k, c_k+1)      eqs. (3)-(4) support, (5)-(6) flight
         p_0 = p_init, v_0 = 0,  p_K = p_f, v_K = 0          start at rest, eq. (8) at the goal

is solved by Gauss-Newton on the hinge of eq. (7): each iteration is one equality-constrained linear
least-squares problem whose KKT matrix, ordered boundary by boundary, is banded, so each iteration
costs O(K) through ``scipy.linalg.solve_banded``. Unlike the paper, which penalises eqs. (3)-(6) and
(8) softly, we impose them exactly (they are linear in the unknowns for fixed T), so the sampled
trajectory satisfies eq. (1) and is continuous to rounding error. The small regularisation w_r keeps
the ZMP near the sole centre where eq. (7) leaves it free (eq. (7) alone has no unique minimiser).

x and y are solved together (eq. (7) couples them through the foot yaw), z separately (eq. (1) is
decoupled per axis for a given T(t)).
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass

import numpy as np
from scipy.linalg import solve_banded

from ..errors import InfeasibleError, InputError
from ..gait import (Footstep, GaitSequence, build_sequence, closing_footstep, footsteps_from_profile,
                    initial_feet, stride_profile)
from ..models.tvlip import flight_state, support_state
from ..stiffness import Stiffness, stiffness as solve_stiffness
from ..swing import swing_path
from ..trajectory import DS, FLIGHT, LEFT, RIGHT, SS, Trajectory

W_REG = 1.0      # ZMP regularisation weight (1/m)
W_HINGE = 1e4    # eq. (7) hinge weight (1/m)
MAX_GN = 50
ZMP_TOL = 1e-3   # a plan whose ZMP leaves eq. (7)'s box by more than this is infeasible, m


@dataclass(frozen=True)
class Boxes:
    """Eq. (7) for every boundary: ZMP box in a local frame.

    Attributes (K+1 boundaries, d = 2 for xy or 1 for z):
        origin: (K+1, d) box frame origin (sole centre or mid-point of both soles), m.
        rot: (K+1, d, d) columns are the local axes in world coordinates (R_foot).
        lo, hi: (K+1, d) bounds of R^T (c - origin), m.

    The origin is also the regularisation target of the ZMP.
    """

    origin: np.ndarray
    rot: np.ndarray
    lo: np.ndarray
    hi: np.ndarray


@dataclass(frozen=True)
class BoundaryPlan:
    """Solution at the phase boundaries: p, v, c of shape (K+1, 3); GN iterations; max eq.-(7) violation (m)."""

    p: np.ndarray
    v: np.ndarray
    c: np.ndarray
    iterations: int
    violation: float
    violation_at: int


# ============================================================================ linear dynamics
def phase_coefficients(kind: np.ndarray, T: np.ndarray, tau: np.ndarray, g: float):
    """Scalar coefficients of eqs. (3)-(6) per phase: next = a . (p, v, c_k, c_k+1) + const_z e_z.

    Returns (ap, av, const) where ap, av have shape (K, 4) and const (K, 2) is the z-only term of
    (p_k+1, v_k+1). Flight phases have zero ZMP coefficients.
    """
    sup = kind != FLIGHT
    Ts = np.where(sup, T, 1.0)
    C, S = np.cosh(tau / Ts), np.sinh(tau / Ts)
    ap = np.where(sup[:, None],
                  np.stack([C, Ts * S, -C + Ts * S / tau, 1 - Ts * S / tau], -1),
                  np.stack([np.ones_like(tau), tau, 0 * tau, 0 * tau], -1))
    av = np.where(sup[:, None],
                  np.stack([S / Ts, C, -1 / tau - S / Ts + C / tau, (1 - C) / tau], -1),
                  np.stack([0 * tau, np.ones_like(tau), 0 * tau, 0 * tau], -1))
    const = np.where(sup[:, None],
                     np.stack([g * Ts**2 * (1 - C), -g * Ts * S], -1),
                     np.stack([-0.5 * g * tau**2, -g * tau], -1))
    return ap, av, const


def _kkt_entries(ap, av, d, K):
    """Constant part of the KKT matrix (dynamics rows and their transposes) as (row, col, val)."""
    blk = 5 * d
    k = np.arange(K)
    rows, cols, vals = [], [], []
    for a in range(d):
        for which, coef in ((0, ap), (1, av)):  # 0 -> position rows, 1 -> velocity rows
            r = k * blk + 3 * d + which * d + a  # multiplier index of this constraint
            var_next = (k + 1) * blk + which * d + a
            targets = [(k * blk + a, -coef[:, 0]), (k * blk + d + a, -coef[:, 1]),
                       (k * blk + 2 * d + a, -coef[:, 2]), ((k + 1) * blk + 2 * d + a, -coef[:, 3]),
                       (var_next, np.ones(K))]
            for col, val in targets:
                rows += [r, col]
                cols += [col, r]
                vals += [val, val]
    return np.concatenate(rows), np.concatenate(cols), np.concatenate(vals)


def _solve_axes(kind, T, tau, g, boxes: Boxes, p0, v0, pK, vK, const_scale: float, dense: bool = False,
                c_start=None):
    """Solve the equality-constrained hinge least squares for d = boxes.origin.shape[1] axes.

    ``const_scale`` multiplies the gravity terms (1 for z, 0 for horizontal axes). ``dense`` solves the
    same KKT system with a dense LU (the O(K^3) baseline of ``gaitshift bench``). ``c_start`` fixes the ZMP
    at boundary 0 (re-planning keeps the ZMP continuous).
    Returns (p, v, c) of shape (K+1, d), iterations, max violation, boundary index of it.
    """
    K = len(kind)
    d = boxes.origin.shape[1]
    blk = 5 * d
    n = K * blk + 3 * d
    ap, av, const = phase_coefficients(kind, T, tau, g)
    r0, c0, v0_ = _kkt_entries(ap, av, d, K)
    # rhs of the dynamics rows
    rhs_dyn = np.zeros(n)
    k = np.arange(K)
    for a in range(d):
        rhs_dyn[k * blk + 3 * d + a] = const[:, 0] * const_scale
        rhs_dyn[k * blk + 4 * d + a] = const[:, 1] * const_scale
    fixed_idx = np.concatenate([np.arange(2 * d), K * blk + np.arange(2 * d)])
    fixed_val = np.concatenate([p0, v0, pK, vK])
    if c_start is not None:
        fixed_idx = np.concatenate([fixed_idx, 2 * d + np.arange(d)])
        fixed_val = np.concatenate([fixed_val, c_start])
    is_fixed = np.zeros(n, bool)
    is_fixed[fixed_idx] = True
    keep = ~is_fixed[r0]
    r0, c0, v0_ = r0[keep], c0[keep], v0_[keep]
    c_idx = (np.arange(K + 1) * blk)[:, None] + 2 * d + np.arange(d)[None, :]  # (K+1, d)

    R, lo, hi, org = boxes.rot, boxes.lo, boxes.hi, boxes.origin
    def solve(active_lo, active_hi):
        # Hessian block per boundary: w_r^2 I + w_h^2 R diag(active) R^T ; gradient rhs likewise
        act = (active_lo | active_hi).astype(float)
        bound = np.where(active_hi, hi, lo) * act
        H = W_REG**2 * np.eye(d)[None] + W_HINGE**2 * np.einsum("kia,ka,kja->kij", R, act, R)
        # stationarity rows of c: H c = w_r^2 c_ref + w_h^2 R (bound + R^T origin) on active components
        rhs_c = W_REG**2 * org \
            + W_HINGE**2 * np.einsum("kia,ka->ki", R, act * (bound + np.einsum("kja,kj->ka", R, org)))
        hr = np.repeat(c_idx, d, axis=1).reshape(-1)
        hc = np.tile(c_idx, (1, d)).reshape(-1)
        hv = H.reshape(-1)
        free = ~is_fixed[hr]
        rows = np.concatenate([r0, hr[free], fixed_idx])
        cols = np.concatenate([c0, hc[free], fixed_idx])
        vals = np.concatenate([v0_, hv[free], np.ones(len(fixed_idx))])
        rhs = rhs_dyn.copy()
        rhs[c_idx.reshape(-1)] = rhs_c.reshape(-1)
        rhs[fixed_idx] = fixed_val
        if dense:
            A = np.zeros((n, n))
            np.add.at(A, (rows, cols), vals)
            return np.linalg.solve(A, rhs)
        lower = int(np.max(rows - cols))
        upper = int(np.max(cols - rows))
        ab = np.zeros((lower + upper + 1, n))
        np.add.at(ab, (upper + rows - cols, cols), vals)
        x = solve_banded((lower, upper), ab, rhs, check_finite=False)
        return x

    def unpack(x):
        idx = np.arange(K + 1) * blk
        p = x[idx[:, None] + np.arange(d)]
        v = x[idx[:, None] + d + np.arange(d)]
        c = x[c_idx]
        return p, v, c

    def local(c):
        return np.einsum("kji,kj->ki", R, c - org)

    active_lo = np.zeros((K + 1, d), bool)
    active_hi = np.zeros((K + 1, d), bool)
    it = 0
    for it in range(1, MAX_GN + 1):
        x = solve(active_lo, active_hi)
        p, v, c = unpack(x)
        u = local(c)
        new_hi = u > hi - 1e-12
        new_lo = u < lo + 1e-12
        # keep a constraint active while the solution sits on its bound (avoid cycling)
        new_hi |= active_hi & (u > hi - 1e-9)
        new_lo |= active_lo & (u < lo + 1e-9)
        if np.array_equal(new_hi, active_hi) and np.array_equal(new_lo, active_lo):
            break
        active_lo, active_hi = new_lo, new_hi
    u = local(c)
    viol = np.maximum(np.maximum(u - hi, lo - u), 0.0).max(axis=1)
    worst = int(np.argmax(viol))
    return p, v, c, it, float(viol[worst]), worst


# ============================================================================ eq. (7) boxes
def build_boxes(seq: GaitSequence, foot_size, margin: float, zmp_z) -> tuple[Boxes, Boxes]:
    """ZMP boxes (xy and z) at every boundary: the sole of the single-support phase next to the
    boundary, or the rectangle spanning both soles when both neighbouring phases are double support."""
    kinds = seq.kind
    on = seq.on
    fs = seq.footstep_array
    K = len(kinds)
    half = np.array([foot_size[0] / 2 - margin, foot_size[1] / 2 - margin])
    prev = np.r_[-1, kinds]  # kind of the phase before / after each boundary (-1: none)
    nxt = np.r_[kinds, -1]
    b = np.arange(K + 1)
    ss = np.where(prev == SS, b - 1, np.where(nxt == SS, b, -1))  # neighbouring single support
    ds = np.where(prev == DS, b - 1, b)  # otherwise a neighbouring double support
    on_ss = on[np.maximum(ss, 0)].max(axis=1)
    on_ds = on[np.minimum(ds, K - 1)]
    a, bb = fs[on_ds[:, LEFT]], fs[on_ds[:, RIGHT]]
    mid_yaw = np.arctan2(np.sin(a[:, 3]) + np.sin(bb[:, 3]), np.cos(a[:, 3]) + np.cos(bb[:, 3]))
    d = a[:, :2] - bb[:, :2]
    sep = np.abs(np.stack([np.cos(mid_yaw) * d[:, 0] + np.sin(mid_yaw) * d[:, 1],
                           -np.sin(mid_yaw) * d[:, 0] + np.cos(mid_yaw) * d[:, 1]], -1))
    is_ss = (ss >= 0)[:, None]
    foot = fs[on_ss]
    origin = np.where(is_ss, foot[:, :2], (a[:, :2] + bb[:, :2]) / 2)
    yaw = np.where(is_ss[:, 0], foot[:, 3], mid_yaw)
    hi = np.where(is_ss, half, half + sep / 2)
    zo = np.where(is_ss[:, 0], foot[:, 2], (a[:, 2] + bb[:, 2]) / 2)
    cy, sy = np.cos(yaw), np.sin(yaw)
    rot = np.stack([np.stack([cy, -sy], -1), np.stack([sy, cy], -1)], -2)  # columns: local x, y
    xy = Boxes(origin, rot, -hi, hi)
    z = Boxes(zo[:, None], np.ones((K + 1, 1, 1)), np.full((K + 1, 1), zmp_z[0]), np.full((K + 1, 1), zmp_z[1]))
    return xy, z


def solve_boundaries(seq: GaitSequence, height: float, g: float, foot_size, margin: float,
                     zmp_z=(0.0, 0.0), dense: bool = False) -> BoundaryPlan:
    """Boundary states and ZMPs for a gait sequence, starting and ending at rest above the mid-feet."""
    kinds, T, tau = seq.kind, seq.stiffness, seq.duration
    on, fs = seq.on, seq.footstep_array
    xy, z = build_boxes(seq, foot_size, margin, zmp_z)
    start = (fs[on[0, LEFT], :3] + fs[on[0, RIGHT], :3]) / 2
    goal = (fs[on[-1, LEFT], :3] + fs[on[-1, RIGHT], :3]) / 2
    p_xy, v_xy, c_xy, it1, viol1, w1 = _solve_axes(kinds, T, tau, g, xy, start[:2], np.zeros(2),
                                                   goal[:2], np.zeros(2), 0.0, dense)
    p_z, v_z, c_z, it2, viol2, w2 = _solve_axes(kinds, T, tau, g, z, start[2:] + height, np.zeros(1),
                                                goal[2:] + height, np.zeros(1), 1.0, dense)
    p = np.hstack([p_xy, p_z])
    v = np.hstack([v_xy, v_z])
    c = np.hstack([c_xy, c_z])
    viol, at = (viol1, w1) if viol1 >= viol2 else (viol2, w2)
    return BoundaryPlan(p, v, c, max(it1, it2), viol, at)


# ============================================================================ sampling
def sample(seq: GaitSequence, bp: BoundaryPlan, g: float, dt: float, swing_height: float) -> dict[str, np.ndarray]:
    """Closed-form sampling of CoM, ZMP and feet at a fixed step ``dt`` (arrays of the contract)."""
    tb = seq.boundary_times
    t_end = tb[-1]
    n = int(math.floor(t_end / dt + 1e-9)) + 1
    t = np.arange(n) * dt
    # a sample within rounding of a boundary starts the new phase
    k = np.clip(np.searchsorted(tb, t + 1e-9 * dt, side="right") - 1, 0, len(seq.phases) - 1)
    s = np.maximum(t - tb[k], 0.0)
    kinds, T = seq.kind[k], seq.stiffness[k]
    sup = kinds != FLIGHT
    pos, vel, acc, zmp = _evaluate(seq, bp, k, s, g)
    out = {
        "t": t,
        "com_pos": pos,
        "com_vel": vel,
        "com_acc": acc,
        "zmp": zmp,
        "phase": kinds.astype(np.int8),
        "stiffness": np.where(sup, T, np.nan),
        "command_vel": np.full((n, 2), np.nan),
    }
    on = seq.on
    out["contact"] = on[k] >= 0
    out["foot_pos"] = _feet(seq, t, k, swing_height)
    return out


def _evaluate(seq: GaitSequence, bp: BoundaryPlan, k: np.ndarray, s: np.ndarray, g: float):
    """CoM position, velocity, acceleration and ZMP, each (len(k), 3), at time ``s`` into phase ``k``:
    eqs. (1)-(4) in support, (5)-(6) in flight (ZMP NaN)."""
    n = len(k)
    sup = seq.kind[k] != FLIGHT
    p, v, a = np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3))
    c = np.full((n, 3), np.nan)
    ks = k[sup]
    p[sup], v[sup], a[sup], c[sup] = support_state(bp.p[ks], bp.v[ks], bp.c[ks], bp.c[ks + 1], seq.stiffness[ks],
                                                   seq.duration[ks], s[sup], g)
    kf = k[~sup]
    p[~sup], v[~sup], a[~sup] = flight_state(bp.p[kf], bp.v[kf], s[~sup], g)
    return p, v, a, c


def _feet(seq: GaitSequence, t: np.ndarray, k: np.ndarray, swing_height: float) -> np.ndarray:
    """Sole centres (N, 2, 3): fixed on their footstep in contact, swing paths in between."""
    on = seq.on
    fs = seq.footstep_array
    tb = seq.boundary_times
    K = len(on)
    feet = np.empty((len(t), 2, 3))
    for side in (LEFT, RIGHT):
        # per phase: footstep before (last contact) and after (next contact), lift-off/touchdown times
        idx = on[:, side]
        last = np.maximum.accumulate(np.where(idx >= 0, np.arange(K), -1))
        nxt = np.where(idx >= 0, np.arange(K), K)
        nxt = np.minimum.accumulate(nxt[::-1])[::-1]
        from_fs = idx[np.maximum(last, 0)]
        to_fs = idx[np.minimum(nxt, K - 1)]
        t_lift = tb[np.maximum(last, 0) + 1]
        t_land = tb[np.minimum(nxt, K - 1)]
        ph_in = idx[k] >= 0
        pos = np.empty((len(t), 3))
        pos[ph_in] = fs[idx[k][ph_in], :3]
        sw = ~ph_in
        if np.any(sw):
            kk = k[sw]
            u = (t[sw] - t_lift[kk]) / (t_land[kk] - t_lift[kk])
            pos[sw] = swing_path(fs[from_fs[kk], :3], fs[to_fs[kk], :3], swing_height, u)
        feet[:, side] = pos
    return feet


# ============================================================================ scenario -> plan
def sequence_for(sc) -> tuple[GaitSequence, Stiffness]:
    """Stiffness values and the gait sequence of a :class:`~gaitshift.scenario.TvlipScenario`."""
    tm = sc.timing
    k = solve_stiffness(sc.height, tm.single_support, tm.double_support, tm.flight, sc.gravity)
    gaits = [seg.gait for seg in sc.gait for _ in range(seg.steps)]
    n = len(gaits)
    first = LEFT if sc.first_swing == "left" else RIGHT
    width = sc.profile.step_width
    if sc.footsteps is None:
        pr = sc.profile
        if pr.max_stride > sc.limits.max_stride:
            raise InputError("profile.max_stride", pr.max_stride, f"(0, {sc.limits.max_stride}] (limits.max_stride, the reach limit)")
        if abs(pr.step_height) > sc.limits.max_step_height:
            raise InputError("profile.step_height", pr.step_height,
                             f"[-{sc.limits.max_step_height}, {sc.limits.max_step_height}] (limits.max_step_height)")
        strides = stride_profile(n, pr.max_stride, pr.accelerate_steps, pr.decelerate_steps)
        feet = footsteps_from_profile(n, first, strides, width, pr.yaw_rate, pr.step_height)
    else:
        feet = initial_feet(width)
        side = first
        prev = feet[1 - first]
        for i, (x, y, z, yaw) in enumerate(sc.footsteps):
            fwd = (x - prev.x) * math.cos(prev.yaw) + (y - prev.y) * math.sin(prev.yaw)
            if abs(fwd) > sc.limits.max_stride:
                raise InputError(f"footsteps[{i}]", [x, y, z, yaw],
                                 f"a stride within +/-{sc.limits.max_stride} m of the previous foothold (limits.max_stride)")
            if abs(z - prev.z) > sc.limits.max_step_height:
                raise InputError(f"footsteps[{i}]", [x, y, z, yaw],
                                 f"a rise within +/-{sc.limits.max_step_height} m (limits.max_step_height)")
            prev = Footstep(x, y, z, yaw, side)
            feet.append(prev)
            side = 1 - side
        feet.append(closing_footstep(prev, width))
    seq = build_sequence(gaits, feet, k, tm.single_support, tm.double_support, tm.flight, tm.start, tm.stop)
    return seq, k


def plan_sequence(seq: GaitSequence, height: float, g: float, foot_size, margin: float, zmp_z,
                  dt: float, swing_height: float) -> tuple[dict[str, np.ndarray], BoundaryPlan]:
    """Solve and sample; raise :class:`InfeasibleError` if the ZMP cannot stay in eq. (7)'s box."""
    bp = solve_boundaries(seq, height, g, foot_size, margin, zmp_z)
    if bp.violation > ZMP_TOL:
        tb = seq.boundary_times
        raise InfeasibleError(
            f"footsteps: the ZMP must leave the sole by {bp.violation * 1e3:.1f} mm at t = {tb[bp.violation_at]:.3f} s "
            f"(phase boundary {bp.violation_at}); allowed: within the sole minus foot.zmp_margin "
            f"(shorten the stride, widen foot.size, or change the timing)")
    return sample(seq, bp, g, dt, swing_height), bp


def plan_scenario(sc) -> Trajectory:
    """Plan a TV-LIPM scenario and return the sampled :class:`Trajectory`."""
    t0 = time.perf_counter()
    seq, k = sequence_for(sc)
    data, bp = plan_sequence(seq, sc.height, sc.gravity, sc.foot.size, sc.foot.zmp_margin, sc.foot.zmp_z,
                             sc.dt, sc.swing_height)
    elapsed = time.perf_counter() - t0
    meta = {
        "planner": "tvlip",
        "gravity": sc.gravity,
        "foot_size": list(sc.foot.size),
        "height": sc.height,
        "dt": sc.dt,
        "stiffness": k.as_dict(),
        "iterations": bp.iterations,
        "max_zmp_violation": bp.violation,
        "plan_time_s": elapsed,
        "step_gait": list(seq.step_gait),
        "scenario": json.loads(sc.model_dump_json()),
    }
    extras = {
        "boundary_t": seq.boundary_times,
        "boundary_com_pos": bp.p,
        "boundary_com_vel": bp.v,
        "boundary_zmp": bp.c,
        "phase_kind": seq.kind,
        "phase_stiffness": np.nan_to_num(seq.stiffness, nan=0.0),
    }
    return Trajectory(**data, footsteps=seq.footstep_array, footstep_side=seq.footstep_side, meta=meta,
                      extras=extras)


# ============================================================================ re-planning from measurements
class Replanner:
    """Re-plan the horizontal CoM/ZMP of the rest of a TV-LIPM plan from a measured CoM state.

    The footsteps, phase timing and stiffness stay; the horizontal boundary states and ZMPs of the
    remaining phases are solved again (same exact-dynamics problem, O(remaining phases)) from the
    measured horizontal position and velocity at time ``t``, mid-phase included. The vertical motion
    keeps the original plan (with fixed T and the ZMP on the sole, eq. (1) leaves no freedom in z).

    Use: ``r = Replanner.from_scenario(sc)``; each step call ``r.replan(t, p_xy, v_xy)``; query the
    reference with ``r.reference(t)`` -> (p, v, a, c) arrays of shape (len(t), 3).
    """

    def __init__(self, seq: GaitSequence, bp: BoundaryPlan, height: float, g: float, foot_size, margin: float,
                 zmp_z=(0.0, 0.0)):
        self.seq, self.height, self.g = seq, height, g
        self.foot_size, self.margin, self.zmp_z = foot_size, margin, zmp_z
        self._t0 = 0.0
        self._seq, self._bp = seq, bp
        self._orig_bp = bp

    @classmethod
    def from_scenario(cls, sc) -> "Replanner":
        seq, _ = sequence_for(sc)
        bp = solve_boundaries(seq, sc.height, sc.gravity, sc.foot.size, sc.foot.zmp_margin, sc.foot.zmp_z)
        return cls(seq, bp, sc.height, sc.gravity, sc.foot.size, sc.foot.zmp_margin, sc.foot.zmp_z)

    @property
    def duration(self) -> float:
        return float(self.seq.boundary_times[-1])

    def replan(self, t: float, p_xy, v_xy) -> BoundaryPlan:
        """Re-solve the horizontal plan from time ``t`` (s) with measured CoM ``p_xy``, ``v_xy``.

        Raises:
            InfeasibleError: the measured state cannot be brought to rest at the goal with the ZMP
                inside eq. (7)'s boxes (the robot needs other footsteps).
        """
        tb = self.seq.boundary_times
        t = float(np.clip(t, 0.0, tb[-1] - 1e-6))
        k = int(np.clip(np.searchsorted(tb, t, side="right") - 1, 0, len(self.seq.phases) - 1))
        first = self.seq.phases[k]
        phases = (type(first)(first.kind, float(tb[k + 1] - t), first.stiffness, first.on),) + self.seq.phases[k + 1:]
        sub = GaitSequence(phases, self.seq.footsteps, self.seq.step_gait)
        xy, _ = build_boxes(sub, self.foot_size, self.margin, self.zmp_z) if first.kind != FLIGHT else \
            _boxes_from_flight(sub, self.foot_size, self.margin, self.zmp_z)
        goal = self._orig_bp.p[-1]
        c_now = None
        if first.kind != FLIGHT:  # keep the ZMP continuous: start from the current reference ZMP
            c_now = self.reference(t)[3][0, :2]
        p, v, c, it, viol, at = _solve_axes(sub.kind, sub.stiffness, sub.duration, self.g, xy,
                                            np.asarray(p_xy, float), np.asarray(v_xy, float),
                                            goal[:2], np.zeros(2), 0.0, c_start=c_now)
        if viol > ZMP_TOL:
            raise InfeasibleError(f"measured state at t = {t:.3f} s: the ZMP must leave the sole by "
                                  f"{viol * 1e3:.1f} mm at t = {t + sub.boundary_times[at]:.3f} s to stop at the goal; "
                                  f"allowed: within the sole (the footsteps must change)")
        # vertical: the original plan evaluated at t, then its remaining boundaries
        pz, vz, _, cz = self._vertical_at(k, t)
        bz = self._orig_bp
        pz_all = np.r_[pz, bz.p[k + 1:, 2]]
        vz_all = np.r_[vz, bz.v[k + 1:, 2]]
        cz_all = np.r_[cz, bz.c[k + 1:, 2]]
        bp = BoundaryPlan(np.c_[p, pz_all], np.c_[v, vz_all], np.c_[c, cz_all], it, viol, at)
        self._seq, self._bp, self._t0 = sub, bp, t
        return bp

    def _vertical_at(self, k: int, t: float):
        bp, seq = self._orig_bp, self.seq
        s = t - seq.boundary_times[k]
        kind = seq.kind[k]
        if kind == FLIGHT:
            p, v, _ = flight_state(bp.p[k], bp.v[k], s, self.g)
            return p[2], v[2], None, bp.c[k, 2]
        p, v, a, c = support_state(bp.p[k], bp.v[k], bp.c[k], bp.c[k + 1], seq.stiffness[k], seq.duration[k], s,
                                   self.g)
        return p[2], v[2], a[2], c[2]

    def reference(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """CoM position, velocity, acceleration and ZMP (each (len(t), 3)) of the current plan at
        absolute times ``t`` >= the last re-planning time. The ZMP is NaN in flight."""
        t = np.atleast_1d(np.asarray(t, float))
        tb = self._t0 + self._seq.boundary_times
        K = len(self._seq.phases)
        k = np.clip(np.searchsorted(tb, t + 1e-12, side="right") - 1, 0, K - 1)
        s = np.clip(t - tb[k], 0.0, self._seq.duration[k])
        return _evaluate(self._seq, self._bp, k, s, self.g)


def _boxes_from_flight(sub: GaitSequence, foot_size, margin, zmp_z):
    """Boxes when the first (truncated) phase is a flight: boundary 0's ZMP does not act; give it the
    box of the landing boundary so that the regularisation has a target."""
    xy, z = build_boxes(GaitSequence(sub.phases[1:], sub.footsteps, sub.step_gait), foot_size, margin, zmp_z)
    first = lambda b: Boxes(*(np.concatenate([arr[:1], arr]) for arr in (b.origin, b.rot, b.lo, b.hi)))
    return first(xy), first(z)
