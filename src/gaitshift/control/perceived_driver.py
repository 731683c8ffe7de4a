"""Closed-loop driver of a TV-LIPM plan (paper 001) on terrain the robot perceives (``--terrain perceived``).

The run starts on the blind plan: flat ground at the height the robot stands on. At every phase
boundary ``k`` the driver reads the terrain it believes in off the controller's elevation map
(:func:`~gaitshift.control.perception.terrain_belief.terrain_belief`) and moves the footholds that
are not committed yet (their swing has not started, :func:`~gaitshift.planners.tvlip.resolve.lift_phase`)
onto it:

* **where**: the safe place nearest the planned foothold's x (eq. (1) of
  :mod:`gaitshift.control.perception.footholds`: the sole on one piece, ``edge_margin`` of the sole
  length from a step edge, the stride and the rise within the scenario's ``limits``, on seen ground);
* **how high**: the believed height under the sole centre, plus the scenario's own offset;
* **in the plane** (``footholds: plane``; the default ``profile`` skips it): first the planned place
  is judged on the map in 2-D (a field of blocks: the profile cannot tell one foot's block from the
  other's; eq. (1) of :mod:`gaitshift.control.perception.patches`): it stays where no step is seen
  under the sole, at its own cells' height, else it moves to the nearest level, seen patch within
  reach, along x and y,
  within the stride and rise limits, and the step feedback keeps its corrected touchdown in that
  patch's room. Where the map cannot say (the place mostly unseen, nothing level within reach), the
  profile's place above stands;
* **the swing**: windowed over the believed edges (:class:`~gaitshift.gait.swing.EdgeClearance`), the
  scenario's ``edge_clearance`` above them;
* **no safe place**: the walk stops before it. That foothold and every later one are set beside the
  last safe one (the remaining steps step in place and the plan ends standing there), and
  :attr:`PerceivedDriver.stopped` says where and why.

The rest of the plan, from boundary ``k``, is then solved again on these footholds from the plan's own
state at ``t_k`` (eq. (1) of :mod:`gaitshift.planners.tvlip.resolve`): the CoM's position, velocity and
ZMP stay continuous, and its height follows the believed treads. Before ``t_k`` the plan is the old one,
and so is a swing in the air at ``t_k`` until it lands (its target was committed). The capture-point
step feedback stays on (:mod:`gaitshift.control.feedback`): this driver moves footholds for the terrain,
not for the measured state.

A re-plan whose ZMP must leave the sole by more than ``max_violation`` m is not taken (the old plan
goes on; :attr:`PerceivedDriver.refused` counts them).

**The lead.** The re-plan for boundary ``k`` changes nothing before ``t_k``, so it can be made earlier:
at the first tick at or after ``t_k - lead`` (``lead`` = ``replan_lead`` s, 0 by default), on the map as
it is then. The plan tracked is the same until ``t_k`` either way. A background worker
(:mod:`gaitshift.control.replanner`) is handed a copy of the map at those instants
(:meth:`PerceivedDriver.map_instants`) and has ``lead`` s to finish before the plan is needed: with a
lead longer than the re-plan takes, the tick never computes one and never waits for one, and the plans
are the inline ones of the same lead.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from gaitshift.control.perception.elevation_map import ElevationMap
from gaitshift.control.perception.footholds import FootholdRules, place
from gaitshift.control.perception.patches import PatchRules, level_patch
from gaitshift.control.perception.terrain_belief import Belief, BeliefSettings, terrain_belief
from gaitshift.errors import check_choice, number_in
from gaitshift.gait.footsteps import Footstep
from gaitshift.gait.swing import EdgeClearance
from gaitshift.models.terrain import Terrain
from gaitshift.planners.tvlip.kkt import BoundaryPlan
from gaitshift.planners.tvlip.planner import sequence_for, trajectory_of
from gaitshift.planners.tvlip.resolve import lift_phase, resolve_from
from gaitshift.planners.tvlip.sampling import sample
from gaitshift.scenario.sim_settings import FOOTHOLD_RULES
from gaitshift.scenario.terrain import terrain_of
from gaitshift.trajectory.contract import Trajectory

__all__ = ["SIGHT_PHASES", "PerceivedDriver", "PerceivedSettings"]

#: a foothold whose swing starts within this many phases of the re-plan must lie on seen ground
SIGHT_PHASES = 1
#: m, footholds and edges that moved less than this do not re-plan (the map's noise is a few mm)
SAME_TOL = 0.002


@dataclass(frozen=True)
class PerceivedSettings:
    """``edge_margin``: share of the sole length a foothold keeps from a step edge; ``max_violation``:
    m, the largest eq.-(7) violation of a re-plan taken; ``belief``: how the map becomes terrain;
    ``replan_lead``: s, how long before each phase boundary its re-plan is made (module docstring, "The
    lead"; a scenario's ``sim: replan_lead``); ``footholds``: one of
    :data:`~gaitshift.scenario.sim_settings.FOOTHOLD_RULES` (a scenario's ``sim: footholds``;
    ``plane``: module docstring, "in the plane")."""

    edge_margin: float = 0.25
    max_violation: float = 0.005
    belief: BeliefSettings = field(default_factory=BeliefSettings)
    replan_lead: float = 0.0
    footholds: str = "profile"

    def __post_init__(self) -> None:
        number_in("replan_lead", self.replan_lead, (0.0, 1.0), "s")
        check_choice("footholds", self.footholds, FOOTHOLD_RULES)


class PerceivedDriver:
    """Drive a TV-LIPM plan over perceived terrain (module docstring).

    Args:
        blind: the scenario as the blind planner plans it (its terrain flat where the robot stands).
        plan: the blind plan (:func:`gaitshift.planners.tvlip.planner.plan_scenario` of ``blind``).
        settings: the driver's settings.

    Attributes:
        trajectory: the plan as known now. replans: re-plans taken. refused: re-plans not taken.
        belief: the terrain believed at the last re-plan. stopped: why the walk stops before an edge
        (None: it does not).
    """

    perceives = True  # the controller hands it the map (:meth:`see`)

    def __init__(self, blind: Any, plan: Trajectory, settings: PerceivedSettings | None = None) -> None:
        self.sc, self.settings = blind, settings or PerceivedSettings()
        self.seq, _ = sequence_for(blind)
        self.lift = lift_phase(self.seq)  # the phases never change, so neither does when each swing starts
        ex = plan.extras
        self.bp = BoundaryPlan(ex["boundary_com_pos"], ex["boundary_com_vel"], ex["boundary_zmp"], 0, 0.0, 0)
        self.nominal = self.seq.footsteps
        self.z0 = float(terrain_of(blind.terrain).height(0.0))
        self.belief = terrain_of(blind.terrain)
        self.trajectory = plan
        self.duration_bound = float(plan.t[-1])
        self.step_feedback = True
        self.replans = self.refused = 0
        self.stopped: str | None = None
        lim = blind.limits
        length, width = (float(v) for v in blind.foot.size)
        margin = self.settings.edge_margin * length
        self.rules = FootholdRules(length, width, margin, float(lim.max_stride), float(lim.max_step_height))
        self.patch = PatchRules(length, width, margin)
        self.rooms: dict[int, tuple[float, float, float, float]] = {}  # foothold index -> its patch's room
        self.moved: set[int] = set()  # the footholds the map last moved off their planned place
        self.map: ElevationMap | None = None
        self.next = 1  # the next boundary to re-plan at
        ys = np.array([f.y for f in self.nominal])
        w = float(blind.foot.size[1])
        self.band = (float(ys.min()) - w, float(ys.max()) + w)

    def see(self, emap: ElevationMap) -> None:
        """The map read at the next re-plan: the controller's own (inline), or a copy of it made at one of
        :meth:`map_instants` (a background worker)."""
        self.map = emap

    def map_instants(self) -> np.ndarray:
        """(B,) plan times s at which the driver reads its map: ``lead`` s before each boundary it may
        re-plan at (the phases, and so these times, never change)."""
        tb = self.seq.boundary_times
        return np.asarray(tb[1 : max(1, len(tb) - 2)], dtype=float) - self.settings.replan_lead

    def maybe_replan(self, t: float, _com: np.ndarray, _com_vel: np.ndarray) -> Trajectory | None:
        """At the first tick at or after ``lead`` s before a phase boundary: the footholds on the believed
        terrain and the rest of the plan solved again from the boundary (module docstring); None when
        nothing changed or no boundary. The measured CoM is not used: the capture-point step feedback
        answers the state, this driver the terrain."""
        tb, lead = self.seq.boundary_times, self.settings.replan_lead
        if self.next >= len(tb) - 2 or t + lead + 1e-9 < tb[self.next]:
            return None
        k = int(np.searchsorted(tb, t + lead + 1e-9, side="right") - 1)
        self.next = k + 1
        belief = self._belief(k)
        if belief is None:
            return None
        free = self.lift >= k
        feet, stopped = self._footholds(np.flatnonzero(free), k, belief)
        moved = any(not _same(f, g) for f, g, c in zip(feet, self.seq.footsteps, free, strict=True) if c)
        if not moved and _same_edges(belief.terrain, self.belief):
            return None
        self.stopped = stopped
        return self._replan(k, feet, belief.terrain)

    def _footholds(self, free: np.ndarray, k: int, belief: Belief) -> tuple[list[Footstep], str | None]:
        """The footsteps with the ``free`` ones (indices, in order) on the believed terrain, and why the
        walk stops (None: it does not; module docstring). Only a foothold whose swing starts within
        :data:`SIGHT_PHASES` phases must lie on seen ground: the later ones will be placed again."""
        feet = list(self.seq.footsteps)
        for n, j in enumerate(free):
            f, p = self.nominal[j], feet[j - 1]
            seen_to = belief.seen[1] if self.lift[j] <= k + SIGHT_PHASES else None
            x = place(belief.terrain, seen_to, f.x, f.yaw, (p.x, p.z), self.rules, belief.gaps)
            if x is None:
                why = (
                    f"stopped at x = {p.x:.2f} m: no safe foothold within reach ahead (a rise beyond "
                    "limits.max_step_height, or ground not seen yet)"
                )
                for i in free[n:]:  # the rest beside the last safe foothold: step in place, end standing
                    g = self.nominal[i]
                    feet[i] = Footstep(p.x, g.y, p.z, p.yaw, g.side)
                return feet, why
            offset = f.z - self.z0  # the scenario's own height of the foothold above the ground
            feet[j] = Footstep(x, f.y, offset + float(belief.terrain.height(x)), f.yaw, f.side)
            if self.settings.footholds == "plane":
                planned = Footstep(f.x, f.y, offset + float(belief.terrain.height(f.x)), f.yaw, f.side)
                feet[j] = self._in_plane(j, planned, p, offset, float(belief.terrain.slope(f.x))) or feet[j]
        return feet, None

    def _in_plane(self, j: int, f: Footstep, prev: Footstep, offset: float, slope: float) -> Footstep | None:
        """Foothold ``j`` planned at ``f`` (at the profile's height there), judged on the map in 2-D (module
        docstring, "in the plane"; ``offset`` m: the scenario's own height above the ground; ``slope``:
        the profile's dz/dx there): kept where no step is seen under it, at its own cells' height, else
        moved to the nearest level patch within reach, or to the place
        the last re-plan moved it to while that is within reach and still level (choices that flip
        between two patches from one map to the next are no plan). None (the profile decides) where the
        map cannot say, or the patch breaks the stride or rise limits from ``prev``. Its room is kept
        (:attr:`rooms`)."""
        emap = self.map
        found = None if emap is None else level_patch(emap, f.x, f.y, f.yaw, self.patch, slope)
        if emap is not None and found is not None and found.moved and j in self.moved:  # a step under it
            last = self.seq.footsteps[j]
            near = abs(last.x - f.x) <= self.patch.reach[0] and abs(last.y - f.y) <= self.patch.reach[1]
            kept = level_patch(emap, last.x, last.y, f.yaw, self.patch, slope) if near else None
            found = kept if kept is not None and not kept.moved else found
        self.rooms.pop(j, None)
        self.moved.discard(j)
        if found is None:
            return None
        z = offset + found.z
        if abs(found.x - prev.x) > self.rules.max_stride or abs(z - prev.z) > self.rules.max_rise:
            return None
        self.rooms[j] = found.room
        if (found.x, found.y) != (f.x, f.y):
            self.moved.add(j)
        return Footstep(found.x, found.y, z, f.yaw, f.side)

    def _belief(self, k: int) -> Belief | None:
        """The terrain believed at boundary ``k``: the map, with the soles stood on filling the unseen."""
        if self.map is None:
            return None
        half = 0.5 * float(self.sc.foot.size[0])
        on = self.seq.on[: k + 1]
        stood = np.unique(on[on >= 0])
        rows = [(f.x - half, f.x + half, f.z) for f in (self.seq.footsteps[j] for j in stood)]
        return terrain_belief(self.map, *self.band, self.settings.belief, rows)

    def _replan(self, k: int, feet: list[Footstep], belief: Terrain) -> Trajectory | None:
        """The plan re-solved from boundary ``k`` on ``feet`` over ``belief`` (module docstring)."""
        sc, old = self.sc, self.trajectory
        seq, bp = resolve_from(
            self.seq, self.bp, k, feet, sc.height, sc.gravity, sc.foot.size, sc.foot.zmp_margin, sc.foot.zmp_z
        )
        if bp.violation > self.settings.max_violation:
            self.refused += 1
            return None
        edges = None if belief.flat else EdgeClearance(belief, sc.foot.size[0], sc.edge_clearance, True)
        kept = np.zeros(seq.on.shape, dtype=bool)  # the past and a swing in the air keep their samples
        kept[:k] = True
        on, ends = seq.on, [round(float(t) / sc.dt) for t in seq.boundary_times]
        for side in (0, 1):  # a swing in the air at t_k keeps its committed path until it lands
            if k > 0 and on[k, side] < 0 and on[k - 1, side] < 0:
                land = k + int(np.argmax(on[k:, side] >= 0))
                kept[k:land, side] = True
        try:
            data = sample(seq, bp, sc.gravity, sc.dt, sc.swing_height, edges, kept)
        except ValueError:  # no swing window clears the believed edges
            self.refused += 1
            return None
        for name, arr in data.items():
            if name != "t":
                arr[: ends[k]] = getattr(old, name)[: ends[k]]
        for side in (0, 1):
            last = k + int(np.argmin(kept[k:, side])) if not kept[k:, side].all() else len(kept)
            data["foot_pos"][ends[k] : ends[last], side] = old.foot_pos[ends[k] : ends[last], side]
        meta = dict(old.meta) | {"terrain": belief.as_list(), "max_zmp_violation": bp.violation, "perceived": True}
        meta["stopped"] = self.stopped  # a host whose driver is a background worker's reads it here
        meta["foothold_rooms"] = [list(self.rooms[j]) for j in sorted(self.rooms)]
        self.seq, self.bp, self.belief = seq, bp, belief
        self.replans += 1
        self.trajectory = trajectory_of(seq, bp, data, meta, sc.dt)
        return self.trajectory


def _same(a: Footstep, b: Footstep, tol: float = SAME_TOL) -> bool:
    """Whether two footholds are the same within ``tol`` m."""
    return abs(a.x - b.x) <= tol and abs(a.y - b.y) <= tol and abs(a.z - b.z) <= tol


def _same_edges(a: Terrain, b: Terrain, tol: float = SAME_TOL) -> bool:
    """Whether two beliefs have the same breaks (x, and the heights either side) within ``tol`` m: the
    swings' windows depend on nothing else."""
    xa, xb = a.breaks(), b.breaks()
    if len(xa) != len(xb) or np.any(np.abs(xa - xb) > tol):
        return False
    side = np.r_[xa - 1e-6, xa + 1e-6]
    return bool(np.all(np.abs(a.height(side) - b.height(side)) <= tol))
