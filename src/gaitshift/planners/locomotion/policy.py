"""What the generator aims at, step by step: the applied command, the ramped target, the gait of the
next step, the stop and the goto.

* Inputs (:meth:`TargetPolicy.command`, :meth:`~TargetPolicy.goto`, :meth:`~TargetPolicy.stop`):
  the command is clamped to the limits (:func:`.command.clamp_command`); a goto replaces it with the
  commands of :func:`.goto.goto_command`, re-computed at every step.
* Per step (:meth:`~TargetPolicy.update`): the target moves toward the command by at most the
  per-step acceleration (:func:`.command.ramp`), and its turn is kept to one the feet can make at its
  speed (:func:`.orbit.feasible_yaw_rate`). When closing on a goal the target is zero speed and the
  yaw rate that brings the heading onto the goal's yaw.
* :meth:`~TargetPolicy.next_type`: the committed type of the next step, by hysteresis on the target
  speed and the successor table, or the ``stop`` when it is due.
* :meth:`~TargetPolicy.soften`: if the limits forbid this step's target change from the current
  state, the largest share of it that still has an exact plan.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace

import numpy as np

from gaitshift.models.arrays import FloatArray
from gaitshift.planners.locomotion.command import clamp_command, finite_real, next_gait, ramp
from gaitshift.planners.locomotion.goto import Goal, goto_command
from gaitshift.planners.locomotion.orbit import Orbit, feasible_yaw_rate
from gaitshift.planners.locomotion.params import LocomotionParams
from gaitshift.planners.locomotion.planner import Instant, Plan, plan_instant, touchdown_offset
from gaitshift.planners.locomotion.steps import SUCCESSOR, Gait, StepType

__all__ = ["ZERO", "TargetPolicy"]

#: a target speed below this is "zero" (m/s, rad/s)
ZERO = 1e-9
#: reports an event: (kind, field, requested, applied, note)
EventSink = Callable[[str, str, float, float, str], None]
WALKABLE = ("walk", "run_to_walk", "start")


class TargetPolicy:
    """The command side of the generator (module docstring).

    Attributes:
        cmd: the applied command (vx, vy m/s in the heading frame, yaw rate rad/s).
        target: the target of the last planning instant (the command ramped).
        stopping: a stop (or a goto's closing) is under way. goal: the goto goal, or None.
        halt: the user requested the stop (it outlasts a goto's closing: the robot stays stopped).
    """

    def __init__(
        self, params: LocomotionParams, types: dict[str, StepType], orbits: dict[str, Orbit], event: EventSink
    ) -> None:
        self.p, self.types, self.orbits, self._event = params, types, orbits, event
        self.cmd = np.zeros(3)
        self.target = np.zeros(3)
        self.stopping = False
        self.halt = False
        self.goal: Goal | None = None
        self._closing = 0  # walking steps left before the goal's closing stop

    # ------------------------------------------------------------------ inputs
    def stride_speed(self) -> FloatArray:
        """Largest |vx|, |vy|, |yaw rate| the foothold limits allow in the fastest allowed gait."""
        lim, tm = self.p.limits, self.p.timing
        period = tm.walk_single + tm.double if self.p.gait == "walk" else tm.run_single + tm.flight
        lateral = max(0.0, min(self.p.step_width - lim.width[0], lim.width[1] - self.p.step_width))
        return np.array([lim.max_stride / period, lateral / period, lim.max_turn / period])

    def command(self, vx: float, vy: float, yaw_rate: float, ended: bool) -> FloatArray:
        """Apply a command (clamped; ignored once ``ended`` or stopping, with an event). Returns the
        command in force.

        Raises:
            InputError: a non-finite component.
        """
        applied, clamps = clamp_command([vx, vy, yaw_rate], self.p.limits, self.stride_speed())
        if self.stopping or ended:
            names = ("command.vx", "command.vy", "command.yaw_rate")
            for name, req, cur in zip(names, (vx, vy, yaw_rate), self.cmd, strict=True):
                if req != cur:
                    self._event("ignored", name, req, cur, "stop requested")
            return self.cmd.copy()
        for c in clamps:
            self._event("clamp", c.field, c.requested, c.applied, c.reason)
        self.goal = None
        self.cmd = applied
        return applied.copy()

    def goto(self, x: float, y: float, yaw: float, ended: bool) -> None:
        """Set a goal pose (world frame, m and rad).

        Raises:
            InputError: a non-finite value (names the field).
        """
        x, y, yaw = (
            finite_real(n, v, "m, or rad for yaw") for n, v in (("goto.x", x), ("goto.y", y), ("goto.yaw", yaw))
        )
        if self.stopping or ended:
            self._event("ignored", "goto", 0.0, 0.0, "stop requested")
            return
        self.goal = Goal(np.array([x, y], dtype=np.float64), float(yaw))
        self._event("goto", "goto", float(np.hypot(x, y)), float(yaw), "goal set")

    def stop(self) -> None:
        """Request the stop: the command becomes zero and the target ramps down to it. A goal not yet
        in reach is dropped (the robot stops where it can); a goto already closing on its goal ends
        there, and the robot then stays stopped."""
        self.halt = True
        if self.goal is not None and not self.stopping:
            self.goal = None
            self._event("ignored", "goto", 0.0, 0.0, "goal dropped: stop requested")
        if not self.stopping:
            self.stopping = True
            self.cmd = np.zeros(3)
            self._event("stop", "stop", 1.0, 1.0, "stop requested")

    def wants_to_move(self) -> bool:
        """A non-zero command or a goal, and no stop requested."""
        return (bool(np.any(np.abs(self.cmd) > ZERO)) or self.goal is not None) and not self.stopping

    def goal_reached(self) -> None:
        """A goto's stop has ended: stand still, ready for new commands (stopped if the user asked)."""
        self.goal, self.stopping = None, self.halt
        self.cmd = np.zeros(3)
        self.target = np.zeros(3)

    # ------------------------------------------------------------------ per step
    def update(self, this: StepType, com: FloatArray, heading: float) -> None:
        """Set the target of the step ``this`` that starts now, with the CoM (2,) and heading there."""
        self._steer(com, heading)
        if self.goal is not None and self.stopping:
            self._close_target(this, heading)
        else:
            self.target = ramp(self.target, self.cmd, self.p.limits.max_accel, 2.0 * this.duration)
            self._limit_turn(this)

    def _steer(self, com: FloatArray, heading: float) -> None:
        """Goto mode: the command from the pose error; close on the goal when it is in reach."""
        if self.goal is None or self.stopping:
            return
        speed = float(np.hypot(self.target[0], self.target[1]))
        step = self.p.timing.walk_single + self.p.timing.double
        cmd, arrive = goto_command(self.goal, com, heading, speed, self.p, step)
        self.cmd, _ = clamp_command(cmd, self.p.limits, self.stride_speed())
        if arrive:
            self.stopping, self._closing = True, 1
            self.cmd = np.zeros(3)
            self._event("goto", "goal", 1.0, 1.0, "closing on the goal")

    def _close_target(self, this: StepType, psi: float) -> None:
        """Goto closing: zero speed, and the yaw rate that brings the heading onto the goal yaw when
        the last foot before the stop touches down (the stop's feet take the goal yaw)."""
        assert self.goal is not None
        if this.name == "stop":
            self.target = np.zeros(3)
            return
        t_td = touchdown_offset(this) if self._closing == 0 else this.duration + self.p.timing.walk_single
        err = (self.goal.yaw - psi + math.pi) % (2.0 * math.pi) - math.pi
        self.target = np.array([0.0, 0.0, err / max(t_td, self.p.dt)])

    def _limit_turn(self, this: StepType) -> None:
        """Keep the target's turn one the feet can make at its speed; an event names a reduction."""
        speed = float(np.hypot(self.target[0], self.target[1]))
        steady = "run" if self.desired_gait(this.gait, self.gait_speed()) == Gait.RUN else "walk"
        lim = self.p.limits
        w = feasible_yaw_rate(
            self.orbits[steady], self.target[:2], float(self.target[2]), self.p.step_width, lim.width, lim.max_stride
        )
        if w != self.target[2]:
            self._event(
                "clamp",
                "command.yaw_rate",
                float(self.target[2]),
                w,
                f"the tightest turn the feet can make at {speed:.2f} m/s ({steady})",
            )
            self.target[2] = w

    # ------------------------------------------------------------------ gait
    def gait_speed(self) -> float:
        """The speed the gait is chosen on: the larger of the target's and the command's, m/s. A
        command above v_up switches to running at once instead of walking ever faster up the ramp; a
        stop from a run keeps running until the ramped-down target is below v_down."""
        return float(max(np.hypot(self.target[0], self.target[1]), np.hypot(self.cmd[0], self.cmd[1])))

    def desired_gait(self, current: Gait, speed: float) -> Gait:
        """The gait selection (:func:`.command.next_gait`) from the gait of ``current`` (also while the
        speed ramps down to a stop: a fast stop keeps running until below v_down)."""
        if current == Gait.STAND:
            current = Gait.RUN if self.p.gait == "run" else Gait.WALK
        return next_gait(current, speed, self.p.gait, self.p.walk_to_run, self.p.run_to_walk)

    def gait_after(self, nxt: str) -> Gait:
        """The gait the horizon continues with after the committed next step ``nxt``."""
        return self.desired_gait(self.types[nxt].gait, self.gait_speed())

    def next_type(self, this: StepType) -> str | None:
        """The committed type of the step after ``this`` (None after the stop)."""
        if this.name == "stop":
            return None
        speed = float(np.hypot(self.target[0], self.target[1]))
        resting = speed < ZERO and abs(self.target[2]) < ZERO
        walkable = this.name in WALKABLE
        if self.goal is not None and self.stopping:  # goto: one more walking step, then the stop
            if self._closing > 0 or not walkable:
                self._closing = max(0, self._closing - 1)
                return SUCCESSOR[(this.name, Gait.WALK)]
            return "stop"
        if self.stopping and resting and walkable:
            return "stop"
        gait = Gait.WALK if self.stopping and resting else self.desired_gait(this.gait, self.gait_speed())
        return SUCCESSOR[(this.name, gait)]

    def closing(self, nxt: str | None) -> bool:
        """True when the horizon must end on the ``stop`` step: it is the next step, or a goto closes."""
        return nxt == "stop" or (self.goal is not None and self.stopping)

    # ------------------------------------------------------------------ infeasible targets
    def soften(self, inst: Instant, plan: Plan, previous: FloatArray) -> tuple[Plan, Instant]:
        """The target change of this instant is more than the limits allow from the current state:
        take the largest share ``a`` of it (``previous + a (target - previous)``, bisection over 7
        halvings) that still has an exact plan, so the ramp slows down instead of the plan giving up
        its target. Returns the plan and instant used (the input ones when no share is exact)."""
        wanted = self.target.copy()
        best: tuple[Plan, Instant, float] | None = None
        lo, hi = 0.0, 1.0
        for k in range(8):
            a = 0.0 if k == 0 else 0.5 * (lo + hi)
            tgt = previous + a * (wanted - previous)
            trial = replace(inst, velocity=tgt[:2].copy(), yaw_rate=float(tgt[2]))
            p = plan_instant(trial, self.p, self.orbits)
            if p.exact:
                best, lo = (p, trial, a), a
            elif k == 0:
                break
            else:
                hi = a
        if best is None:
            return plan, inst
        self.target = previous + best[2] * (wanted - previous)
        self._event("ramp", "target", 1.0, best[2], "the share of this step's target change the limits allow")
        return best[0], best[1]
