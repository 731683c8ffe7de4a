"""Re-planning a TV-LIPM plan (paper 001) from a measured CoM state, mid-phase included."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from gaitshift.errors import InfeasibleError, InputError
from gaitshift.gait.sequence import GaitSequence, Phase
from gaitshift.models.arrays import FloatArray, FloatLike
from gaitshift.models.tvlip import flight_state, support_state
from gaitshift.planners.tvlip.boxes import boxes_from_flight, build_boxes
from gaitshift.planners.tvlip.kkt import BoundaryPlan, solve_axes
from gaitshift.planners.tvlip.planner import ZMP_TOL, sequence_for, solve_boundaries
from gaitshift.planners.tvlip.sampling import evaluate
from gaitshift.scenario.tvlip import TvlipScenario
from gaitshift.trajectory.contract import FLIGHT

__all__ = ["Replanner"]


class Replanner:
    """Re-plan the horizontal CoM/ZMP of the rest of a TV-LIPM plan from a measured CoM state.

    The footsteps, phase timing and stiffness stay; the horizontal boundary states and ZMPs of the
    remaining phases are solved again (same exact-dynamics problem, O(remaining phases)) from the
    measured horizontal position and velocity at time ``t``, mid-phase included. The vertical motion
    keeps the original plan (with fixed T and the ZMP on the sole, eq. (1) leaves no freedom in z).

    Use: ``r = Replanner.from_scenario(sc)``; each step call ``r.replan(t, p_xy, v_xy)``; query the
    reference with ``r.reference(t)`` -> (p, v, a, c) arrays of shape (len(t), 3).
    """

    def __init__(
        self,
        seq: GaitSequence,
        bp: BoundaryPlan,
        height: float,
        g: float,
        foot_size: Sequence[float],
        margin: float,
        zmp_z: Sequence[float] = (0.0, 0.0),
    ):
        self.seq, self.height, self.g = seq, height, g
        self.foot_size, self.margin, self.zmp_z = foot_size, margin, zmp_z
        self._t0 = 0.0
        self._seq, self._bp = seq, bp
        self._orig_bp = bp

    @classmethod
    def from_scenario(cls, sc: TvlipScenario) -> Replanner:
        """The plan of ``sc`` (boundary solve only, no sampling), ready to re-plan."""
        seq, _ = sequence_for(sc)
        bp = solve_boundaries(seq, sc.height, sc.gravity, sc.foot.size, sc.foot.zmp_margin, sc.foot.zmp_z)
        return cls(seq, bp, sc.height, sc.gravity, sc.foot.size, sc.foot.zmp_margin, sc.foot.zmp_z)

    @property
    def duration(self) -> float:
        """Duration of the whole plan, s."""
        return float(self.seq.boundary_times[-1])

    def replan(self, t: float, p_xy: FloatArray, v_xy: FloatArray) -> BoundaryPlan:
        """Re-solve the horizontal plan from time ``t`` (s) with measured CoM ``p_xy``, ``v_xy`` (2,).

        Raises:
            InputError: ``t`` outside [0, start of the closing stand), ``p_xy`` or ``v_xy`` not 2 finite
                numbers of magnitude <= :data:`MAX_POSITION` m / :data:`MAX_SPEED` m/s.
            InfeasibleError: the measured state cannot be brought to rest at the goal with the ZMP
                inside eq. (7)'s boxes (the robot needs other footsteps).
        """
        p_xy, v_xy = _measured("p_xy", p_xy, MAX_POSITION), _measured("v_xy", v_xy, MAX_SPEED)
        tb = self.seq.boundary_times
        if isinstance(t, bool) or not isinstance(t, int | float | np.floating) or not 0.0 <= t < tb[-2]:
            raise InputError(
                "t", t, f"a time in [0, {tb[-2]:g}) s (before the closing stand: nothing is left to re-plan)"
            )
        t = float(t)
        k = int(np.clip(np.searchsorted(tb, t, side="right") - 1, 0, len(self.seq.phases) - 1))
        first = self.seq.phases[k]
        phases = (Phase(first.kind, float(tb[k + 1] - t), first.stiffness, first.on), *self.seq.phases[k + 1 :])
        sub = GaitSequence(phases, self.seq.footsteps, self.seq.step_gait)
        boxes = boxes_from_flight if first.kind == FLIGHT else build_boxes
        xy, _ = boxes(sub, self.foot_size, self.margin, self.zmp_z)
        goal = self._orig_bp.p[-1]
        c_now = None
        if first.kind != FLIGHT:  # keep the ZMP continuous: start from the current reference ZMP
            c_now = self.reference(t)[3][0, :2]
        h = solve_axes(
            sub.kind,
            sub.stiffness,
            sub.duration,
            self.g,
            xy,
            np.asarray(p_xy, float),
            np.asarray(v_xy, float),
            goal[:2],
            np.zeros(2),
            0.0,
            c_start=c_now,
        )
        if h.violation > ZMP_TOL:
            raise InfeasibleError(
                f"measured state at t = {t:.3f} s: the ZMP must leave the sole by "
                f"{h.violation * 1e3:.1f} mm at t = {t + sub.boundary_times[h.violation_at]:.3f} s to stop at the "
                f"goal; allowed: within the sole (the footsteps must change)"
            )
        # vertical: the original plan evaluated at t, then its remaining boundaries
        pz, vz, cz = self._vertical_at(k, t)
        bz = self._orig_bp
        pz_all = np.r_[pz, bz.p[k + 1 :, 2]]
        vz_all = np.r_[vz, bz.v[k + 1 :, 2]]
        cz_all = np.r_[cz, bz.c[k + 1 :, 2]]
        bp = BoundaryPlan(
            np.c_[h.p, pz_all], np.c_[h.v, vz_all], np.c_[h.c, cz_all], h.iterations, h.violation, h.violation_at
        )
        self._seq, self._bp, self._t0 = sub, bp, t
        return bp

    def _vertical_at(self, k: int, t: float) -> tuple[float, float, float]:
        """Vertical CoM position, velocity and ZMP of the original plan at time t in phase k (in
        flight the ZMP is the boundary value, which does not act)."""
        bp, seq = self._orig_bp, self.seq
        s = t - seq.boundary_times[k]
        if seq.kind[k] == FLIGHT:
            p, v, _ = flight_state(bp.p[k], bp.v[k], s, self.g)
            return float(p[2]), float(v[2]), float(bp.c[k, 2])
        p, v, _, c = support_state(bp.p[k], bp.v[k], bp.c[k], bp.c[k + 1], seq.stiffness[k], seq.duration[k], s, self.g)
        return float(p[2]), float(v[2]), float(c[2])

    def reference(self, t: FloatLike) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """CoM position, velocity, acceleration and ZMP (each (len(t), 3)) of the current plan at
        absolute times ``t`` >= the last re-planning time. The ZMP is NaN in flight."""
        try:
            t = np.atleast_1d(np.asarray(t, float))
        except (TypeError, ValueError):
            raise InputError("t", t, "finite times, s") from None
        if t.ndim != 1 or not np.all(np.isfinite(t)):
            raise InputError("t", t, "finite times, s (a number or a 1-D sequence)")
        tb = self._t0 + self._seq.boundary_times
        K = len(self._seq.phases)
        k = np.clip(np.searchsorted(tb, t + 1e-12, side="right") - 1, 0, K - 1)
        s = np.clip(t - tb[k], 0.0, self._seq.duration[k])
        return evaluate(self._seq, self._bp, k, s, self.g)


#: largest measured horizontal CoM position, m, and speed, m/s, a re-plan accepts (beyond them the
#: hyperbolic terms of eq. (1) overflow to NaN references; no robot is there)
MAX_POSITION = 1e4
MAX_SPEED = 100.0


def _measured(field: str, value: Any, bound: float) -> np.ndarray:
    """A measured horizontal CoM quantity: 2 finite numbers of magnitude <= ``bound`` (m or m/s), else
    :class:`InputError`."""
    allowed = f"2 finite numbers of magnitude <= {bound:g}"
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise InputError(field, value, allowed) from None
    if a.shape != (2,) or not np.all(np.abs(a) <= bound):
        raise InputError(field, value, allowed)
    return a
