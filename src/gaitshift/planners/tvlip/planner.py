"""TV-LIPM planner of paper 001 §II-B: CoM and ZMP over given footsteps, from a scenario to a plan.

The pipeline: the scenario's gait and footsteps become a :class:`~gaitshift.gait.sequence.GaitSequence`
(:func:`sequence_for`), the boundary states and ZMPs are solved under eq. (7)
(:func:`solve_boundaries`, the banded KKT of :mod:`gaitshift.planners.tvlip.kkt` over the boxes of
:mod:`gaitshift.planners.tvlip.boxes`), and the closed forms are sampled
(:mod:`gaitshift.planners.tvlip.sampling`). x and y are solved together (eq. (7) couples them through
the foot yaw), z separately (eq. (1) is decoupled per axis for a given T(t)).
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Sequence
from typing import Any

import numpy as np

from gaitshift.errors import InfeasibleError, InputError
from gaitshift.gait.footsteps import (
    Footstep,
    closing_footstep,
    footsteps_from_profile,
    initial_feet,
    on_terrain,
    stride_profile,
)
from gaitshift.gait.sequence import GaitSequence, build_sequence
from gaitshift.gait.swing import EdgeClearance, foot_yaws, mid_heading
from gaitshift.models.arrays import FloatArray
from gaitshift.models.stiffness import Stiffness
from gaitshift.models.stiffness import stiffness as solve_stiffness
from gaitshift.planners.tvlip.boxes import build_boxes
from gaitshift.planners.tvlip.kkt import BoundaryPlan, phase_coefficients, solve_axes
from gaitshift.planners.tvlip.sampling import sample
from gaitshift.scenario.terrain import terrain_of
from gaitshift.scenario.tvlip import TvlipScenario
from gaitshift.trajectory.contract import LEFT, RIGHT, Trajectory

__all__ = ["ZMP_TOL", "plan_scenario", "plan_sequence", "sequence_for", "solve_boundaries", "trajectory_of"]

ZMP_TOL = 1e-3  # a plan whose ZMP leaves eq. (7)'s box by more than this is infeasible, m


def solve_boundaries(
    seq: GaitSequence,
    height: float,
    g: float,
    foot_size: Sequence[float],
    margin: float,
    zmp_z: Sequence[float] = (0.0, 0.0),
    dense: bool = False,
) -> BoundaryPlan:
    """Boundary states and ZMPs for a gait sequence, starting and ending at rest above the mid-feet
    (CoM ``height`` m above the mid-point of the soles). ``dense`` uses the dense KKT baseline."""
    kinds, T, tau = seq.kind, seq.stiffness, seq.duration
    on, fs = seq.on, seq.footstep_array
    xy, z = build_boxes(seq, foot_size, margin, zmp_z)
    start = (fs[on[0, LEFT], :3] + fs[on[0, RIGHT], :3]) / 2
    goal = (fs[on[-1, LEFT], :3] + fs[on[-1, RIGHT], :3]) / 2
    coef = phase_coefficients(kinds, T, tau, g)
    h = solve_axes(kinds, T, tau, g, xy, start[:2], np.zeros(2), goal[:2], np.zeros(2), 0.0, dense, coefficients=coef)
    z0, zK = start[2:] + height, goal[2:] + height
    v = solve_axes(kinds, T, tau, g, z, z0, np.zeros(1), zK, np.zeros(1), 1.0, dense, coefficients=coef)
    viol, at = (h.violation, h.violation_at) if h.violation >= v.violation else (v.violation, v.violation_at)
    return BoundaryPlan(
        np.hstack([h.p, v.p]), np.hstack([h.v, v.v]), np.hstack([h.c, v.c]), max(h.iterations, v.iterations), viol, at
    )


def _profile_footsteps(sc: TvlipScenario, n: int, first: int) -> list[Footstep]:
    """Footsteps of the scenario's stride profile (checked against the limits)."""
    pr = sc.profile
    if pr.max_stride > sc.limits.max_stride:
        raise InputError(
            "profile.max_stride", pr.max_stride, f"(0, {sc.limits.max_stride}] (limits.max_stride, the reach limit)"
        )
    if abs(pr.step_height) > sc.limits.max_step_height:
        raise InputError(
            "profile.step_height",
            pr.step_height,
            f"[-{sc.limits.max_step_height}, {sc.limits.max_step_height}] (limits.max_step_height)",
        )
    strides = stride_profile(n, pr.max_stride, pr.accelerate_steps, pr.decelerate_steps)
    return footsteps_from_profile(n, first, strides, pr.step_width, pr.yaw_rate, pr.step_height)


def _listed_footsteps(sc: TvlipScenario, first: int) -> list[Footstep]:
    """The scenario's explicit footsteps (checked against the limits) plus the closing step."""
    assert sc.footsteps is not None
    width = sc.profile.step_width
    feet = initial_feet(width)
    side = first
    prev = feet[1 - first]
    for i, (x, y, z, yaw) in enumerate(sc.footsteps):
        fwd = (x - prev.x) * math.cos(prev.yaw) + (y - prev.y) * math.sin(prev.yaw)
        if abs(fwd) > sc.limits.max_stride:
            raise InputError(
                f"footsteps[{i}]",
                [x, y, z, yaw],
                f"a stride within +/-{sc.limits.max_stride} m of the previous foothold (limits.max_stride)",
            )
        if abs(z - prev.z) > sc.limits.max_step_height:
            raise InputError(
                f"footsteps[{i}]",
                [x, y, z, yaw],
                f"a rise within +/-{sc.limits.max_step_height} m (limits.max_step_height)",
            )
        prev = Footstep(x, y, z, yaw, side)
        feet.append(prev)
        side = 1 - side
    feet.append(closing_footstep(prev, width))
    return feet


def sequence_for(sc: TvlipScenario) -> tuple[GaitSequence, Stiffness]:
    """Stiffness values and the gait sequence of a :class:`~gaitshift.scenario.tvlip.TvlipScenario`."""
    tm = sc.timing
    k = solve_stiffness(sc.height, tm.single_support, tm.double_support, tm.flight, sc.gravity)
    gaits = [seg.gait for seg in sc.gait for _ in range(seg.steps)]
    first = LEFT if sc.first_swing == "left" else RIGHT
    feet = _profile_footsteps(sc, len(gaits), first) if sc.footsteps is None else _listed_footsteps(sc, first)
    try:
        feet = on_terrain(feet, terrain_of(sc.terrain), sc.foot.size)
    except ValueError as exc:
        i, why = str(exc).split(": ", 1)
        raise InputError("terrain", f"foothold {i}", f"soles clear of its edges ({why})") from None
    seq = build_sequence(gaits, feet, k, tm.single_support, tm.double_support, tm.flight, tm.start, tm.stop)
    return seq, k


def plan_sequence(
    seq: GaitSequence,
    height: float,
    g: float,
    foot_size: Sequence[float],
    margin: float,
    zmp_z: Sequence[float],
    dt: float,
    swing_height: float,
    edges: EdgeClearance | None = None,
) -> tuple[dict[str, FloatArray], BoundaryPlan]:
    """Solve and sample (swings clear the terrain's ``edges``); raise :class:`InfeasibleError` if the
    ZMP cannot stay in eq. (7)'s box."""
    bp = solve_boundaries(seq, height, g, foot_size, margin, zmp_z)
    if bp.violation > ZMP_TOL:
        tb = seq.boundary_times
        raise InfeasibleError(
            f"footsteps: the ZMP must leave the sole by {bp.violation * 1e3:.1f} mm at t = {tb[bp.violation_at]:.3f} s "
            f"(phase boundary {bp.violation_at}); allowed: within the sole minus foot.zmp_margin "
            f"(shorten the stride, widen foot.size, or change the timing)"
        )
    return sample(seq, bp, g, dt, swing_height, edges), bp


def plan_scenario(sc: TvlipScenario) -> Trajectory:
    """Plan a TV-LIPM scenario and return the sampled :class:`Trajectory`."""
    t0 = time.perf_counter()
    seq, k = sequence_for(sc)
    terrain = terrain_of(sc.terrain)
    edges = None if terrain.flat else EdgeClearance(terrain, sc.foot.size[0], sc.edge_clearance)
    try:
        data, bp = plan_sequence(
            seq, sc.height, sc.gravity, sc.foot.size, sc.foot.zmp_margin, sc.foot.zmp_z, sc.dt, sc.swing_height, edges
        )
    except ValueError as exc:
        if isinstance(exc, InputError):
            raise
        raise InputError("swing_height", sc.swing_height, f"a swing that clears the terrain ({exc})") from None
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
        "terrain": terrain.as_list(),
        "edge_clearance": sc.edge_clearance,
        "scenario": json.loads(sc.model_dump_json()),
    }
    return trajectory_of(seq, bp, data, meta, sc.dt)


def trajectory_of(
    seq: GaitSequence, bp: BoundaryPlan, data: dict[str, FloatArray], meta: dict[str, Any], dt: float
) -> Trajectory:
    """The :class:`Trajectory` of a solved plan: the samples ``data`` of :func:`plan_sequence` (step
    ``dt`` s), the boundary plan in ``extras``, foot yaws, headings and each sample's gait."""
    extras: dict[str, np.ndarray] = {
        "boundary_t": seq.boundary_times,
        "boundary_com_pos": bp.p,
        "boundary_com_vel": bp.v,
        "boundary_zmp": bp.c,
        "phase_kind": seq.kind,
        "phase_stiffness": np.nan_to_num(seq.stiffness, nan=0.0),
    }
    fs, side = seq.footstep_array, seq.footstep_side
    foot_yaw = foot_yaws(data["contact"].astype(bool), data["foot_pos"], fs, side)
    tb = seq.boundary_times
    phase_of = np.clip(np.searchsorted(tb, data["t"] + 1e-9 * dt, side="right") - 1, 0, len(seq.phases) - 1)
    fields: dict[str, Any] = dict(data)
    return Trajectory(
        **fields,
        footsteps=fs,
        footstep_side=side,
        heading=mid_heading(foot_yaw),
        foot_yaw=foot_yaw,
        gait=seq.phase_gait[phase_of],
        command_yaw_rate=np.full(len(data["t"]), np.nan),
        meta=meta,
        extras=extras,
    )
