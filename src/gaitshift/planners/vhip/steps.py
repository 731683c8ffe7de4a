"""The step planner of the online VHIP generator (paper 003): plan segments into the plan buffer.

:class:`StepPlanner` writes the run into a plan buffer (:mod:`.emission`), one segment per planning
instant, and keeps the swing feet (:mod:`.swings`) and the record of planned steps (:class:`Takeoff`):

* :meth:`StepPlanner.start`: State Switching 1, standing to the first take-off, then the first running
  step.
* :meth:`StepPlanner.run_step`: at a take-off, the step after the next one (State Switching 2): the
  commanded take-off velocity under the per-step and stride limits (:mod:`.limits`) and its foothold
  by Algorithm 1 (:mod:`.foothold`); the CoM of that step is eq. (13) over the running horizon.
* :meth:`StepPlanner.stop`: State Switching 3, the last stance and the final double support to rest.
* :meth:`StepPlanner.replan`: the next step again from a measured CoM state, propagated by eq. (9').

Limits that change a value are reported as :class:`Event` s at the time passed to each call.
"""

from __future__ import annotations

import numpy as np

from gaitshift.models.arrays import FloatArray
from gaitshift.models.vhip import row_weights
from gaitshift.planners.streaming.events import Event, Takeoff
from gaitshift.planners.vhip.emission import contact_of, plan_buffer, write_segment
from gaitshift.planners.vhip.foothold import FootholdResult, target_foothold
from gaitshift.planners.vhip.horizons import VhipHorizons
from gaitshift.planners.vhip.limits import clamp_by_strides, clip_change, stride_window
from gaitshift.planners.vhip.swings import FootTracks
from gaitshift.planners.vhip.switching import SwitchingSolution
from gaitshift.planners.vhip.transitions import solve_start, solve_stop
from gaitshift.scenario.vhip import VhipScenario
from gaitshift.trajectory.contract import FLIGHT, LEFT, RIGHT, SS

__all__ = ["AXES", "StepPlanner"]

#: the fields named in events, per axis
AXES = ("command.vx", "command.vy")


class StepPlanner:
    """The planned segments of one VHIP run (see module doc).

    Attributes:
        buf: the plan buffer; feet: the swing feet; events: where limits are reported (shared).
        footholds: every foothold planned so far, ((2,) m, side).
        stance_sides, stance_feet: side and foothold (2,) of every planned stance.
        takeoffs: every planned step.
        last_cmd_target: commanded part (2,) of the last planned take-off velocity, m/s.
        last_target: the last planned take-off velocity (2,), m/s.
        end: last sample of the stop (at rest), None before the stop is planned.
        rest_zmp: ZMP (2,) at rest after the stop, m.
        start_solution, stop_solution: the State Switching 1 and 3 solutions, once planned.
    """

    def __init__(self, sc: VhipScenario, h: VhipHorizons, events: list[Event]):
        self.sc, self.h, self.events = sc, h, events
        self.first = LEFT if sc.first_support == "left" else RIGHT
        d = 0.5 * h.width
        self.feet = FootTracks({LEFT: np.array([0.0, d, 0.0]), RIGHT: np.array([0.0, -d, 0.0])}, sc.swing_apex, h.dt)
        self.buf = plan_buffer()
        self.footholds: list[tuple[FloatArray, int]] = [
            (self.feet.home[LEFT][:2].copy(), LEFT),
            (self.feet.home[RIGHT][:2].copy(), RIGHT),
        ]
        self.stance_sides: list[int] = []
        self.stance_feet: list[FloatArray] = []
        self.takeoffs: list[Takeoff] = []
        self.last_cmd_target = np.zeros(2)
        self.last_target = np.zeros(2)
        self.end: int | None = None
        self.rest_zmp = np.zeros(2)
        self.start_solution: SwitchingSolution | None = None
        self.stop_solution: SwitchingSolution | None = None

    def _event(self, t: float, kind: str, fld: str, requested: float, applied: float, note: str) -> None:
        self.events.append(Event.at(t, kind, fld, requested, applied, note))

    def _accel_limited(self, t: float, cmd: FloatArray, last: FloatArray) -> tuple[FloatArray, FloatArray]:
        """``cmd`` within max_accel_per_step of ``last`` (changes reported), and that limit (2,)."""
        dv = np.asarray(self.sc.limits.max_accel_per_step, float)
        out = clip_change(cmd, last, dv)
        for k, name in enumerate(AXES):
            if out[k] != cmd[k]:
                self._event(t, "clamp_accel", name, cmd[k], out[k], f"|change| <= {dv[k]} m/s per step")
        return out, dv

    def _clamp_target(
        self, t: float, cmd: FloatArray, side: int, c_prev: FloatArray, v_prev: FloatArray, p_prev: FloatArray
    ) -> FloatArray:
        """Commanded part of the next take-off velocity after the per-step and stride limits."""
        out, dv = self._accel_limited(t, cmd, self.last_cmd_target)
        # foothold of Algorithm 1 in closed form: p = c_prev - v_prev U_0 - v1 V_0 (unit ZMP response is 1)
        K = np.asarray(c_prev) - np.asarray(v_prev) * self.h.U[0] - np.asarray(p_prev)
        lo_d, hi_d = stride_window(1.0 if side == LEFT else -1.0, self.sc.limits.max_stride, self.sc.foot.size[1])
        osc = np.array([0.0, self.h.oscillation(side)])
        v1 = out + osc
        v1c = clamp_by_strides(v1, K, self.h.V[0], lo_d, hi_d, self.last_cmd_target + osc, dv)
        for k, name in enumerate(AXES):
            if v1c[k] != v1[k]:
                note = f"foothold step within [{lo_d[k]:.3f}, {hi_d[k]:.3f}] m"
                self._event(t, "clamp_stride", name, v1[k] - osc[k], v1c[k] - osc[k], note)
        target: FloatArray = v1c - osc
        return target

    def start(self, t: float, cmd: FloatArray) -> int:
        """Plan the start towards ``cmd`` (2,) m/s and the first running step; returns the sample index
        of the first take-off (the next planning instant)."""
        h, side = self.h, self.first
        y1 = self.feet.home[side][:2]
        want, _ = self._accel_limited(t, cmd, np.zeros(2))
        seg = solve_start(h, want, side, y1)
        if seg.scale < 1.0:
            for k, name in enumerate(AXES):
                if want[k] != 0:
                    note = "fastest start keeping the ZMP in the feet"
                    self._event(t, "clamp_start", name, want[k], seg.scale * want[k], note)
        target = seg.scale * want
        n = h.n_start + h.n_sup
        write_segment(self.buf, 0, seg.com, h.start_z, seg.zmp, seg.phase, contact_of(seg.phase, side))
        self.stance_sides.append(side)
        self.stance_feet.append(y1.copy())
        self.feet.set_lift(side, n, self.feet.home[side])
        self.feet.set_lift(1 - side, h.n_start, self.feet.home[1 - side])
        v_end = target + np.array([0.0, h.oscillation(side)])
        self.takeoffs.append(Takeoff(n, n * h.dt, v_end, y1.copy(), np.zeros(2, int), "start"))
        self.last_cmd_target, self.last_target = target, v_end
        self.start_solution = seg.solution
        self.run_step(t, cmd)
        return n

    def _planning_state(self) -> tuple[int, int, FloatArray, FloatArray]:
        """At a planning instant: (side of the next stance, index a of the last planned sample,
        CoM at a (copy), take-off velocity target of the step being flown)."""
        k = len(self.stance_sides)
        side = self.first if k % 2 == 0 else 1 - self.first
        a = self.buf.n - 1
        return side, a, self.buf["c"][a].copy(), self.last_target

    def run_step(self, t: float, cmd: FloatArray) -> None:
        """Plan the next running step towards the commanded speed ``cmd`` (2,) m/s."""
        h = self.h
        side, a, c_prev, v_prev = self._planning_state()
        p_prev = self.stance_feet[-1]
        target = self._clamp_target(t, cmd, side, c_prev, v_prev, p_prev)
        v1 = target + np.array([0.0, h.oscillation(side)])
        sgn = 1.0 if side == LEFT else -1.0
        T = h.n_step * h.dt
        p_nom = p_prev + np.array([v1[0] * T, sgn * h.width + target[1] * T])
        res = self._foothold(c_prev, v_prev, v1, p_nom)
        self._commit_run(a, side, res, v1, target)

    def _foothold(self, c_prev: FloatArray, v_prev: FloatArray, v1: FloatArray, p_nom: FloatArray) -> FootholdResult:
        """Algorithm 1 in coordinates centred on ``c_prev`` (keeps the solve's rounding at the scale
        of one step, not of the distance run), shifted back."""
        res = target_foothold(self.h.run_horizon, np.zeros(2), v_prev, v1, np.asarray(p_nom) - c_prev)
        return FootholdResult(res.foothold + c_prev, res.com + c_prev, res.iterations, res.residual)

    def _commit_run(
        self,
        a: int,
        side: int,
        res: FootholdResult,
        v1: FloatArray,
        target: FloatArray,
        now: int | None = None,
    ) -> None:
        """Write the step after sample ``a``; with ``now`` (the next sample to emit) it replaces the
        last planned step (re-plan) and redirects a swing foot already in the air."""
        h = self.h
        w = h.run_w[1:]
        phase = np.where(w > 0, SS, FLIGHT).astype(np.int8)
        zmp = np.where((w > 0)[:, None], res.foothold[None, :], np.nan)
        z3 = (h.run_z[0][1:], h.run_z[1][1:], h.run_z[2][1:])
        write_segment(self.buf, a + 1, res.com[1:], z3, zmp, phase, contact_of(phase, side))
        touchdown = a + h.n_fly
        end = a + h.n_step
        p3 = np.array([res.foothold[0], res.foothold[1], 0.0])
        takeoff = Takeoff(end, end * h.dt, v1, res.foothold.copy(), res.iterations, "run")
        if now is not None:
            self.footholds[-1] = (res.foothold.copy(), side)
            self.stance_feet[-1] = res.foothold.copy()
            self.takeoffs[-1] = takeoff
            self.feet.redirect(side, now, touchdown, p3)
        else:
            self.stance_sides.append(side)
            self.stance_feet.append(res.foothold.copy())
            self.footholds.append((res.foothold.copy(), side))
            self.feet.swing_to(side, touchdown, p3)
            self.feet.set_lift(side, end, p3)
            self.takeoffs.append(takeoff)
        self.last_cmd_target, self.last_target = target, v1

    def stop(self) -> None:
        """Plan the stop after the last planned take-off (State Switching 3)."""
        h = self.h
        side, a, c_prev, v_prev = self._planning_state()
        seg = solve_stop(h, side, c_prev, v_prev)
        z3 = (h.stop_z[0][1:], h.stop_z[1][1:], h.stop_z[2][1:])
        contact = contact_of(seg.phase, side)
        write_segment(self.buf, a + 1, seg.com[1:], z3, seg.zmp[1:], seg.phase[1:], contact[1:])
        A, B = seg.A, seg.B
        self.stance_sides.append(side)
        self.stance_feet.append(A.copy())
        self.footholds += [(A.copy(), side), (B.copy(), 1 - side)]
        self.feet.swing_to(side, a + h.n_fly, np.append(A, 0.0))
        self.feet.swing_to(1 - side, a + seg.n_ss_end, np.append(B, 0.0))
        self.stop_solution = seg.solution
        self.end = a + len(seg.phase) - 1
        self.rest_zmp = 0.5 * (A + B)

    def replan(self, t: float, pos: FloatArray, vel: FloatArray, i: int, j: int) -> tuple[float, float]:
        """Re-plan from the measured CoM ``pos`` (2,) m, ``vel`` (2,) m/s at sample ``i`` (the next to
        emit): eq. (9') to the take-off at sample ``j``, then the step after it again by Algorithm 1
        (same take-off target unless the stride limits need another). Returns (CoM offset from the
        plan at i, foothold shift), m."""
        h, buf, dt = self.h, self.buf, self.h.dt
        old_c, old_p = buf["c"][i].copy(), self.footholds[-1][0].copy()
        c = self._propagate(pos, vel, i, j)
        buf["c"][i : j + 1] = c
        v_to = (c[-1] - c[-2]) / dt if len(c) > 1 else vel
        side = self.stance_sides[-1]
        tk = self.takeoffs[-1]
        p_prev = self.stance_feet[-2]
        sgn = 1.0 if side == LEFT else -1.0
        osc = np.array([0.0, h.oscillation(side)])
        # same take-off target unless the new foothold would break the stride limits
        target = self._clamp_target(t, tk.target - osc, side, c[-1], v_to, p_prev)
        v1 = target + osc
        p_nom = p_prev + np.array([v1[0] * h.n_step * dt, sgn * h.width])
        res = self._foothold(c[-1], v_to, v1, p_nom)
        self._commit_run(j, side, res, v1, target, now=i)
        return float(np.hypot(*(pos - old_c))), float(np.hypot(*(res.foothold - old_p)))

    def _propagate(self, pos: FloatArray, vel: FloatArray, i: int, j: int) -> FloatArray:
        """Horizontal CoM (j - i + 1, 2) from ``pos``, ``vel`` at sample i to sample j by eq. (9')
        over the planned ZMP and vertical profile (the first step is the forward Euler of eq. (8))."""
        buf, dt = self.buf, self.h.dt
        c = np.empty((j - i + 1, 2))
        c[0] = pos
        if len(c) > 1:
            c[1] = pos + vel * dt
        w = row_weights(buf["z"][i : j + 1], buf["zdd"][i : j + 1], self.h.g, dt)
        p = np.nan_to_num(buf["zmp"][i : j + 1])
        cx, cy = c[:, 0].tolist(), c[:, 1].tolist()
        for k in range(1, len(c) - 1):
            cx[k + 1] = (2 + w[k]) * cx[k] - cx[k - 1] - w[k] * p[k, 0]
            cy[k + 1] = (2 + w[k]) * cy[k] - cy[k - 1] - w[k] * p[k, 1]
        return np.column_stack([cx, cy])
