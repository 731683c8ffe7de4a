"""Closed-loop driver of the locomotion generator: a live generator that follows simulated time, is
re-planned from the measured CoM, and gives the loop a plan that reaches a few steps ahead.

The generator runs at the control period. Its scripted commands (the scenario's ``commands`` and
``stop_at``, :func:`gaitshift.planners.locomotion.plan.script_of`) are applied as simulated time
reaches them. At every planning instant (the start of a step) the next step is planned from the
**measured** CoM position and velocity (:meth:`LocomotionGenerator.replan`), so footholds absorb what
the robot did differently from the plan. The loop needs more than the current sample (swing targets,
lift-off and touchdown times): the driver forks the generator (the emitted history is shared, not
copied) and runs the fork a few planning instants ahead; the fork's trajectory is the plan the loop
tracks until the next planning instant.

That plan is a window of the run (:mod:`gaitshift.trajectory.window`): its samples from
:data:`WINDOW_BACK` before the live generator's next sample to the end of the look-ahead, so that its
cost and its size stay the same however long the run (the whole run's plan grew by 500 samples a second
at 2 ms, and each re-plan copied and derived all of it: docs/deploy.md, "A plan of constant size").
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gaitshift.planners.locomotion.generator import LocomotionGenerator
from gaitshift.planners.locomotion.params import params_from_scenario
from gaitshift.planners.locomotion.plan import script_of
from gaitshift.scenario.facts import RobotFacts
from gaitshift.trajectory.contract import DS, FLIGHT, OPEN_END, Trajectory
from gaitshift.trajectory.window import index_at

__all__ = ["LOOKAHEAD_STEPS", "WINDOW_BACK", "LocomotionDriver"]

#: planning instants the fork runs past the live generator
LOOKAHEAD_STEPS = 3
#: time allowed after the stop request for the ramp-down and the closing step, s
STOP_ALLOWANCE = 20.0
#: how far back the plan reaches from the live generator's next sample, s: past the tick that adopts
#: it (a background re-plan comes up to ~90 ticks late, docs/deploy.md) and the current steps; a foot
#: that stood longer keeps its foothold at the window's first sample (a stance foot does not move)
WINDOW_BACK = 1.0


class LocomotionDriver:
    """Drive a :class:`LocomotionGenerator` through a closed-loop run (module docstring).

    Args:
        scenario: a ``planner: locomotion`` scenario.
        facts: its robot's facts (None: the paper's defaults).
        control_period: the loop's period = the generator's sample step, s.
        replan_gain: share of the measured deviation from the plan (CoM position and velocity) that a
            re-plan takes in. 0 (the default): the generator is not reset to the measurement; the
            loop's step feedback (capture point: swing feet re-aimed from the measured divergent
            component every tick, the plan translated at touchdown, :mod:`gaitshift.control.feedback`)
            corrects the footholds instead (``step_feedback`` True). Measured on the G1
            (docs/locomotion.md "Closed loop"): gains 0.5 and 1 fell in running.

    Attributes:
        trajectory: the plan as known now: a window of the run (module docstring) to the look-ahead's end.
        replans: re-plans from a measured state made so far.
        duration_bound: an upper bound of the run's plan time, s (stop request + allowance).
        step_feedback: True when the loop's capture-point step feedback must stay on.
    """

    def __init__(
        self, scenario: Any, facts: RobotFacts | None, control_period: float, replan_gain: float = 0.0
    ) -> None:
        self.replan_gain = float(replan_gain)
        self.step_feedback = self.replan_gain == 0.0
        self.sc = scenario
        self.gen = LocomotionGenerator(params_from_scenario(scenario.model_copy(update={"dt": control_period}), facts))
        self.script = script_of(scenario)
        self.duration_bound = self.script.stop_at + STOP_ALLOWANCE
        self.replans = 0
        self._done: set[int] = set()
        self._last_kind = DS  # kind of the last phase of the step seen last
        self._steps_seen = -1  # the live generator's step count at the last look-ahead
        self.script.apply_due(self.gen)
        self.trajectory = self._look_ahead()

    @classmethod
    def live(cls, scenario: Any, facts: RobotFacts | None, control_period: float, max_time: float) -> LocomotionDriver:
        """A driver whose commands come live (:meth:`command`, :meth:`stop`) instead of the scenario's
        script; the run is at most ``max_time`` s before the stop."""
        sc = scenario.model_copy(update={"commands": scenario.commands[:1], "stop_at": max_time})
        drv = cls(sc, facts, control_period)
        drv.gen.command(0.0, 0.0, 0.0)
        return drv

    def command(self, vx: float, vy: float, yaw_rate: float) -> None:
        """A live command (m/s in the heading frame, rad/s): it acts from the next planning instant."""
        self.gen.command(vx, vy, yaw_rate)

    def stop(self) -> None:
        """A live stop request."""
        self.gen.stop()

    def _look_ahead(self) -> Trajectory:
        """The plan from the start to a few steps past now: a fork of the live generator run ahead."""
        fork = self.gen.fork()
        script = self.script.remaining()
        for _ in range(LOOKAHEAD_STEPS):
            if fork.finished:
                break
            nxt = fork.next_plan_index
            target = nxt if nxt is not None and nxt > fork.tick_index else None
            if target is None:
                fork.step()
            else:
                script.advance_to(fork, target)
            script.apply_due(fork)
        if fork.finished:  # the robot stands at rest: half a second of it closes the plan
            fork.advance(round(0.5 / fork.dt))
        else:
            fork.step()
        traj = fork.trajectory(since=max(0, self.gen.tick_index - round(WINDOW_BACK / fork.dt)))
        traj.meta[OPEN_END] = not fork.finished  # a look-ahead that a later plan continues
        return traj

    def _extend(self, idx: int) -> Trajectory | None:
        """Refresh the look-ahead when the live generator has planned a new step (the plan the loop
        tracks must contain it), the plan is about to end (a live session standing still), or the
        generator has come to rest while the plan is still open-ended (a stop asked for before any step:
        that plan must close, or the run never ends)."""
        g = self.gen
        near_end = idx >= round(float(self.trajectory.t[-1]) / g.dt) - round(0.2 / g.dt) and not self._ended()
        closing = self._ended() and bool(self.trajectory.meta.get(OPEN_END, False))
        if g.step_count == self._steps_seen and not near_end and not closing:
            return None
        self._steps_seen = g.step_count
        self.trajectory = self._look_ahead()
        return self.trajectory

    def _ended(self) -> bool:
        return bool(self.gen.finished)

    def _due(self, idx: int) -> bool:
        """A re-plan is due at sample ``idx``: the take-off of a running step (its state is the
        flight's, clean of touchdown impacts; the landing foot and the one after it are re-aimed), or
        the start of a step that follows a double support (the swing foot has just lifted)."""
        g = self.gen
        rec = g.current_step
        if rec is None or idx in self._done or g.finished:
            return False
        if rec.i0 < idx < rec.i1 and rec.step.phases[-1].kind == FLIGHT:
            return idx == int(rec.bounds[1])
        prev_ds = self._last_kind != FLIGHT
        return idx == g.next_plan_index and g.tick_index == idx and prev_ds

    def maybe_replan(self, t: float, com: np.ndarray, com_vel: np.ndarray) -> Trajectory | None:
        """Follow simulated time to ``t`` (s); when a re-plan is due (:meth:`_due`), re-plan from the
        measured CoM position and velocity ((3,) m, m/s; horizontal parts; the plan takes
        ``replan_gain`` of their deviation from it) and return the new plan, else None."""
        g = self.gen
        idx = round(t / g.dt)
        if abs(idx * g.dt - t) > 1e-9:
            return None
        self.script.advance_to(g, idx)
        self.script.apply_due(g)
        rec = g.current_step
        if rec is not None and rec.i0 <= idx < rec.i1:
            self._last_kind = rec.step.phases[-1].kind
        if self.replan_gain == 0.0:  # only the look-ahead follows the live generator
            return self._extend(idx)
        if not self._due(idx):
            return None
        j = index_at(self.trajectory, t)
        x_p, v_p = self.trajectory.com_pos[j, :2], self.trajectory.com_vel[j, :2]
        x_m, v_m = np.asarray(com)[:2], np.asarray(com_vel)[:2]
        k = self.replan_gain
        g.replan(x_p + k * (x_m - x_p), v_p + k * (v_m - v_p))
        self._done.add(idx)
        self.replans += 1
        self.trajectory = self._look_ahead()
        return self.trajectory
