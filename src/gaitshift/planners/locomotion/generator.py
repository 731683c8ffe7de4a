"""The locomotion generator: a live (vx, vy, yaw rate) command in, exact CoM/ZMP/feet samples out.

Streaming API (the same shape as :class:`gaitshift.planners.vhip.generator.VhipGenerator`):

* :meth:`LocomotionGenerator.command` sets (vx, vy, yaw_rate), clamped to the limits (events);
* :meth:`~LocomotionGenerator.tick` emits one sample, :meth:`~LocomotionGenerator.advance` n samples,
  :meth:`~LocomotionGenerator.step` up to the next planning instant;
* :meth:`~LocomotionGenerator.replan` re-plans from a measured CoM state;
* :meth:`~LocomotionGenerator.stop` ramps the command to zero and ends at rest;
* :attr:`~LocomotionGenerator.events`, :attr:`~LocomotionGenerator.state`,
  :meth:`~LocomotionGenerator.trajectory`.

It stands until the first non-zero command, starts (``start`` step: the ZMP moves inside the
double support through a free knot), then plans one step at every planning instant (the start of
each step): the target velocity ramps toward the command by at most ``max_accel`` per step, the gait
of the next step is chosen with hysteresis (:mod:`.command`), the step types follow
:data:`~.steps.SUCCESSOR` (walk-to-run and run-to-walk transitions of paper 001), and the footholds
come from :func:`.planner.plan_instant`. Only the current step is sampled; the next instant plans
again from its end state, so a changed command or a measured state acts within two steps.
"""

from __future__ import annotations

import copy
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from gaitshift.common.rotations import mid_yaw, wrap_angle
from gaitshift.errors import InfeasibleError, InputError
from gaitshift.models.arrays import FloatArray
from gaitshift.models.stiffness import stiffness as solve_stiffness
from gaitshift.planners.locomotion.instants import within_step, within_step_unknowns
from gaitshift.planners.locomotion.orbit import Orbit
from gaitshift.planners.locomotion.params import LocomotionParams, params_from_scenario
from gaitshift.planners.locomotion.planner import (
    Instant,
    Plan,
    has_knot,
    horizon,
    is_start,
    plan_instant,
)
from gaitshift.planners.locomotion.policy import TargetPolicy
from gaitshift.planners.locomotion.record import StepRecord, phase_samples
from gaitshift.planners.locomotion.samples import locomotion_meta, trajectory_from
from gaitshift.planners.locomotion.steps import SUCCESSOR, Gait, StepType, build_step_types
from gaitshift.planners.locomotion.writer import StepWriter
from gaitshift.planners.streaming.generator import StreamingGenerator
from gaitshift.planners.streaming.samples import Samples
from gaitshift.scenario.facts import RobotFacts
from gaitshift.scenario.loader import load_scenario
from gaitshift.trajectory.contract import LEFT, RIGHT, Trajectory

__all__ = ["LocomotionGenerator"]


class LocomotionGenerator(StreamingGenerator):
    """Stateful walk/run/turn/stop generator (module docstring) for :class:`LocomotionParams`.

    Attributes:
        p: the parameters; stiffness: the stiffness values of paper 001 for its timing; types: the
        step types; orbits: the periodic orbits of the steady types; policy: the command side
        (:class:`~.policy.TargetPolicy`); writer: buffer, feet and footholds
        (:class:`~.writer.StepWriter`); events: what the generator changed or refused.
    """

    @classmethod
    def from_scenario(cls, scenario: Any, facts: RobotFacts | None = None) -> LocomotionGenerator:
        """The generator of a locomotion scenario (a built-in name, a YAML path or a loaded
        ``planner: locomotion`` scenario) with the numbers of its robot ``facts``
        (:func:`gaitshift.api.robot_facts`; required when the scenario names a robot, whose model the
        planners never load). Commands are given live (:meth:`command`, :meth:`goto`, :meth:`stop`)."""
        sc = load_scenario(scenario) if isinstance(scenario, str | Path) else scenario
        if getattr(sc, "planner", None) != "locomotion":
            raise InputError("scenario", getattr(sc, "name", scenario), "a planner: locomotion scenario")
        if facts is None and getattr(sc, "robot", None) is not None:
            raise InputError("facts", None, f"the facts of robot '{sc.robot}' (gaitshift.api.robot_facts(scenario))")
        return cls(params_from_scenario(sc, facts))

    def __init__(self, params: LocomotionParams, keep_history: bool = True) -> None:
        p = params
        super().__init__(p.dt, keep_history)
        self.p, self.g = p, p.gravity
        tm = p.timing
        self.stiffness = solve_stiffness(p.height, tm.run_single, tm.double, tm.flight, p.gravity)
        self.types: dict[str, StepType] = build_step_types(self.stiffness, tm, p.height, p.gravity)
        self.orbits = {n: Orbit.of(st) for n, st in self.types.items() if st.steady}
        self.policy = TargetPolicy(p, self.types, self.orbits, self._event)
        self.writer = StepWriter(p.dt, p.gravity, p.height, p.step_width, p.swing_height)
        self._rec: StepRecord | None = None
        self._next_type: str | None = None
        self._finished = False
        self._psi_stand = 0.0  # heading while standing
        self._steps = 0

    # ------------------------------------------------------------------ state
    @property
    def state(self) -> str:
        """standing, starting, walking, running, stopping or stopped."""
        if (self._finished and (self._rec is None or self._i >= self._rec.i1)) or (
            self._rec is None and self.policy.stopping
        ):
            return "stopped"
        if self._rec is None:
            return "standing"
        if self.policy.stopping:
            return "stopping"
        if is_start(self._rec.step):
            return "starting"
        return "running" if self._rec.step.gait == 2 else "walking"

    @property
    def command_velocity(self) -> FloatArray:
        """The applied command (vx, vy, yaw_rate) after the limits."""
        return self.policy.cmd.copy()

    @property
    def target(self) -> FloatArray:
        """The target (vx, vy, yaw_rate) of the last planning instant (the command ramped)."""
        return self.policy.target.copy()

    @property
    def step_count(self) -> int:
        """Steps planned so far (the start included)."""
        return self._steps

    @property
    def current_step(self) -> StepRecord | None:
        """The step being emitted (None while standing)."""
        return self._rec

    # ------------------------------------------------------------------ inputs
    def command(self, vx: float, vy: float = 0.0, yaw_rate: float = 0.0) -> FloatArray:
        """Set the command (m/s in the heading frame, rad/s). Returns the applied (clamped) command.

        Raises:
            InputError: a non-finite component.
        """
        return self.policy.command(vx, vy, yaw_rate, self._finished)

    def goto(self, x: float, y: float, yaw: float = 0.0) -> None:
        """Walk to the pose (x, y, yaw) (world frame, m and rad) and stop on it (:mod:`.goto`): the
        feet end side by side, their middle on (x, y), their yaw ``yaw``. A later :meth:`command`
        cancels the goal.

        Raises:
            InputError: a non-finite value (names the field).
        """
        self.policy.goto(x, y, yaw, self._finished)

    def stop(self) -> None:
        """Request the stop: the target ramps to zero, the gait returns to walking, a closing step
        puts the feet side by side, and the CoM comes to rest over their middle."""
        self.policy.stop()

    # ------------------------------------------------------------------ planning
    def heading_at(self, i: int) -> float:
        """The planned heading at sample ``i`` of the current step (or while standing), rad."""
        r = self._rec
        if r is None:
            return self._psi_stand
        return r.psi0 + r.omega * (min(i, r.i1) - r.i0) * self.dt

    def _horizon(self, this: StepType, nxt: str | None, unknowns_before: int) -> tuple[StepType, ...]:
        """The horizon's step types, with the committed next type second."""
        if nxt is None:
            return (this,)
        pol = self.policy
        types = horizon(
            self.types, this.name, nxt, pol.gait_after(nxt), stopping=pol.closing(nxt), unknowns_before=unknowns_before
        )
        return types if types[1].name == nxt else (types[0], self.types[nxt], *types[2:])

    def _start_point(self) -> tuple[str, FloatArray, float, int, FloatArray | None, float]:
        """(type, own point, own yaw, own side, next foot if down, its yaw) of the step that starts now."""
        prev, feet = self._rec, self.writer.feet
        if prev is None:
            first = 1 - self.p.first_swing
            yl, yr = feet[LEFT].rest[3], feet[RIGHT].rest[3]
            own_yaw = mid_yaw(float(yl), float(yr))
            own = 0.5 * (feet[LEFT].rest[:2] + feet[RIGHT].rest[:2])
            name = "start_run" if self.p.gait == "run" else "start"
            return name, own, own_yaw, first, feet[first].rest[:2].copy(), float(feet[first].rest[3])
        assert self._next_type is not None
        return self._next_type, prev.next, prev.next_yaw, prev.next_side, None, prev.next_yaw

    def _plan_step(self) -> None:
        """At a planning instant: set the target, choose the next step type and the footholds, and
        commit the step that starts now (module docstring)."""
        i = self._i
        name, own, own_yaw, own_side, next_fixed, next_yaw = self._start_point()
        psi = self._psi_stand if self._rec is None else self.heading_at(self._rec.i1)
        this = self.types[name]
        pol = self.policy
        previous = pol.target.copy()
        p_end, v_end = self.writer.end_state
        pol.update(this, p_end[:2], psi)
        nxt = pol.next_type(this)
        ph0 = this.phases[0]
        x0, v0 = np.array([p_end[0], p_end[1], ph0.z0]), np.array([v_end[0], v_end[1], ph0.vz0])
        before = int(has_knot(this)) + int(next_fixed is None and not is_start(this) and this.name != "stop")
        goal = pol.goal if pol.stopping else None
        inst = Instant(
            self._horizon(this, nxt, before),
            0,
            0.0,
            0.0,
            x0[:2],
            v0[:2],
            np.asarray(own, float),
            own_yaw,
            own_side,
            next_fixed,
            next_yaw,
            psi,
            float(pol.target[2]),
            pol.target[:2].copy(),
            goal=None if goal is None else goal.xy,
            stop_yaw=None if goal is None else goal.yaw,
        )
        plan = plan_instant(inst, self.p, self.orbits)
        if not plan.exact and nxt == "stop" and goal is None:  # not stoppable yet: one more walking step
            nxt = SUCCESSOR[(name, Gait.WALK)]
            inst = replace(inst, types=self._horizon(this, nxt, before))
            plan = plan_instant(inst, self.p, self.orbits)
            self._event("stop", "stop", 1.0, 0.0, "postponed one step: no rest within the limits yet")
        if not plan.exact and goal is None:
            plan, inst = pol.soften(inst, plan, previous)
        self._commit(this, plan, i, own, own_side, psi, x0, v0)
        self._next_type = nxt
        self._steps += 1

    def _commit(
        self,
        this: StepType,
        plan: Plan,
        i: int,
        own: FloatArray,
        own_side: int,
        psi: float,
        x0: FloatArray,
        v0: FloatArray,
    ) -> None:
        bounds = i + np.concatenate([[0], np.cumsum(phase_samples(this, self.dt))])
        rest = 0.5 * (np.asarray(own) + plan.footholds[0]) if this.name == "stop" else None
        tgt = self.policy.target
        omega = float(tgt[2])
        if this.name == "stop" and self._rec is not None:  # the heading ends on the mean yaw of the feet
            omega = wrap_angle(mid_yaw(self._rec.next_yaw, float(plan.yaws[0])) - psi) / ((bounds[-1] - i) * self.dt)
        rec = StepRecord(
            this,
            i,
            bounds,
            np.asarray(own, float),
            own_side,
            plan.footholds[0].copy(),
            float(plan.yaws[0]),
            int(plan.sides[0]),
            plan.knots.get(0),
            rest,
            psi,
            omega,
            0.0,
            tgt.copy(),
        )
        if not plan.exact:
            self._event("target", "footholds", 0.0, 1.0, "the target state is not reachable within the limits")
        self._rec = rec
        self.writer.commit(rec, plan, x0, v0, self._steps)
        self._next_plan = None if this.name == "stop" else rec.i1

    # ------------------------------------------------------------------ re-planning
    def replan(self, com_pos: npt.ArrayLike, com_vel: npt.ArrayLike) -> None:
        """Re-plan from a measured CoM state at the time of the next sample (:attr:`t`).

        At a planning instant (:attr:`next_plan_index`) the next step is simply planned from the
        measured state. Within a step:

        The horizontal CoM restarts from the measured (x, y) position and velocity; the footholds
        still in the air (the swing target, and in running the one after it) and the start/stop knot
        are solved again (:func:`.planner.plan_instant`), and the swing feet re-target from where
        they are. Feet on the ground stay. The vertical plan is kept (with fixed stiffness and the
        ZMP on the ground, eq. (1) leaves no vertical freedom).

        Raises:
            InputError: a non-finite measurement. InfeasibleError: not stepping (standing or stopped).
        """
        pos = np.asarray(com_pos, dtype=np.float64).ravel()[:2]
        vel = np.asarray(com_vel, dtype=np.float64).ravel()[:2]
        if not (np.all(np.isfinite(pos)) and np.all(np.isfinite(vel))):
            raise InputError("measured CoM state", [*pos.tolist(), *vel.tolist()], "finite numbers")
        rec, i = self._rec, self._i
        if rec is not None and i == rec.i1 and self._next_plan == i:  # a planning instant: plan from it
            p_end, v_end = self.writer.end_state
            self.writer.end_state = (np.array([pos[0], pos[1], p_end[2]]), np.array([vel[0], vel[1], v_end[2]]))
            self._event("replan", "com", 0.0, 0.0, "at a planning instant: the next step starts from the measurement")
            return
        if rec is None or i >= rec.i1 or self.finished:
            raise InfeasibleError(f"replan: only while stepping (state {self.state})")
        next_fixed, before = within_step_unknowns(rec, i, self.dt)
        own_yaw = float(self.writer.feet[rec.own_side].landed(rec.i0)[3]) if not is_start(rec.step) else rec.psi0
        types = self._horizon(rec.step, self._next_type, before)
        inst = within_step(rec, i, self.dt, types, pos, vel, own_yaw, self.heading_at(i), next_fixed)
        plan = plan_instant(inst, self.p, self.orbits)
        old = rec.next.copy()
        if next_fixed is None:
            rec.next = plan.footholds[0].copy()
        if 0 in plan.knots:
            rec.knot = plan.knots[0]
        if rec.step.name == "stop":
            rec.rest = 0.5 * (rec.own + rec.next)
        self.writer.retarget(rec, plan, i, next_fixed is None)
        z, zd = self.writer.vertical_at(i)
        self.writer.sample(rec, i, np.array([pos[0], pos[1], z]), np.array([vel[0], vel[1], zd]), self._steps)
        self._event("replan", "com", 0.0, float(np.hypot(*(rec.next - old))), "applied = foothold shift (m)")

    # ------------------------------------------------------------------ emission
    def _block(self, n: int) -> int:
        """Plan what is due at the current sample and return how many samples can be emitted now."""
        i, pol = self._i, self.policy
        if self._rec is None and not self._finished:
            if pol.stopping:  # a stop while standing: done
                self._finished = True
            if not pol.wants_to_move():
                self.writer.standing(i, i + n, self._psi_stand, self._steps)
                return n
            self._plan_step()
        elif self._next_plan is not None and i == self._next_plan:
            self._plan_step()
        rec = self._rec
        if rec is not None and i < rec.i1:
            return min(n, rec.i1 - i)
        if pol.goal is not None and rec is not None:  # a goto ended: stand, ready for new commands
            self._psi_stand = self.heading_at(rec.i1)
            self._rec, self._next_plan = None, None
            pol.goal_reached()
            self._event("goto", "goal", 1.0, 1.0, "standing on the goal")
            return self._block(n)
        self._finished = True
        self._next_plan = None
        self.writer.standing(i, i + n, self.heading_at(i), self._steps)
        return n

    def _emit(self, m: int) -> Samples:
        """The next ``m`` samples from the writer's buffer, with the applied command."""
        return self.writer.emit(self._i, m, self.policy.cmd)

    def plan_due(self) -> bool:
        """Plan the step that starts at the next sample, if one is due (a planning instant, or a
        first command while standing); True if it planned. :meth:`advance` does this on its own; a
        controller calls it to plan ahead of emitting, and the bench to time planning alone."""
        if (self._next_plan is not None and self._i == self._next_plan) or (
            self._rec is None and not self._finished and self.policy.wants_to_move()
        ):
            self._plan_step()
            return True
        return False

    def step(self) -> Samples:
        """Advance to the next planning instant (the rest of the stop once stopping; one walking
        single-support duration while standing or stopped)."""
        self.plan_due()
        rec = self._rec
        if rec is not None and self._i < rec.i1:
            return self.advance(rec.i1 - self._i)
        return self.advance(max(1, round(self.p.timing.walk_single / self.dt)))

    def fork(self) -> LocomotionGenerator:
        """An independent copy to run ahead (a closed loop's look-ahead); the emitted history, which
        never changes, is shared instead of copied."""
        return copy.deepcopy(self, {id(b): b for b in self.history()})

    # ------------------------------------------------------------------ output
    def trajectory(self, since: int = 0) -> Trajectory:
        """Everything emitted so far as the standard trajectory contract (planner "locomotion"); from the
        run's sample ``since`` on: a window (:mod:`gaitshift.trajectory.window`)."""
        s = self.emitted(since)
        meta = locomotion_meta(self.p, self.stiffness.as_dict(), [e.as_dict() for e in self.events])
        return trajectory_from(s, self.writer.footsteps, self.writer.bounds, meta)
