"""The online VHIP running generator of paper 003: start, run with streamed speed commands, stop.

:class:`VhipGenerator` holds the plan across calls so a controller can call it every control tick:

* :meth:`VhipGenerator.command` sets the commanded speed (vx, vy). Values beyond the scenario
  limits are clamped to the nearest feasible value and reported in :attr:`VhipGenerator.events`.
* :meth:`VhipGenerator.tick` advances one control period and returns that sample;
  :meth:`VhipGenerator.step` advances to the next planning instant (one running step);
  :meth:`VhipGenerator.advance` advances any number of ticks.
* :meth:`VhipGenerator.replan` re-plans from a measured CoM state (position, velocity).
* :meth:`VhipGenerator.stop` requests the stop to standstill.

Timeline. The stance of step k ends with the take-off ``to_k``. At ``to_k`` the foot of stance k
lifts off and swings to the foothold of stance k+2, so that foothold, and the CoM of the step
``(to_{k+1}, to_{k+2}]``, are planned at ``to_k`` by Algorithm 1 (:mod:`.foothold`). A command that
arrives before ``to_k`` is therefore reached exactly at ``to_{k+2}``: the take-off of the second step
after the command, as in the paper (Fig. 7). The start (State Switching 1) and the stop (State
Switching 3) are planned by the segmented ZMP optimisation (:mod:`.transitions`, :mod:`.switching`).

The pieces: the fixed horizons (:mod:`.horizons`), the step planner that writes the plan
(:mod:`.steps`, with the command limits of :mod:`.limits` and the swing feet of :mod:`.swings`), the
plan buffer and the emitted samples (:mod:`.emission`; the buffer, samples, events, scripted commands
and the emission loop are shared with the locomotion generator: :mod:`gaitshift.planners.streaming`). Lateral take-off
speeds are the command plus the periodic oscillation ``-/+ u`` (stance on the left/right foot) whose
footholds are exactly ``step_width`` apart.
"""

from __future__ import annotations

import math

import numpy as np

from gaitshift.errors import InfeasibleError, InputError
from gaitshift.models.arrays import FloatArray
from gaitshift.models.vhip import FORCE_EPS
from gaitshift.planners.streaming.events import Takeoff
from gaitshift.planners.streaming.generator import StreamingGenerator
from gaitshift.planners.streaming.samples import Samples
from gaitshift.planners.streaming.script import Command, CommandScript
from gaitshift.planners.vhip.emission import emit_samples, hold_at_rest
from gaitshift.planners.vhip.horizons import VhipHorizons
from gaitshift.planners.vhip.limits import speed_limit
from gaitshift.planners.vhip.steps import AXES, StepPlanner
from gaitshift.planners.vhip.switching import SwitchingSolution
from gaitshift.scenario.vhip import VhipScenario
from gaitshift.trajectory.contract import RUN, STAND, Trajectory, standing_samples

__all__ = ["VhipGenerator", "plan_scenario", "run_commands"]


class VhipGenerator(StreamingGenerator):
    """Stateful running generator for a :class:`~gaitshift.scenario.vhip.VhipScenario` (see module doc)."""

    def __init__(self, scenario: VhipScenario, keep_history: bool = True):
        """``keep_history=False`` drops emitted samples (a controller that only needs each tick):
        memory then stays bounded, and :meth:`trajectory` is unavailable."""
        sc = scenario
        self.sc = sc
        self._h = h = VhipHorizons.from_scenario(sc)
        super().__init__(h.dt, keep_history)
        self.g = h.g
        self.n_step, self.n_sup, self.n_fly = h.n_step, h.n_sup, h.n_fly
        self.n_start, self.n_stop = h.n_start, h.n_stop
        self.vertical = h.vertical
        self.width = h.width
        #: take-off lateral velocity after a left stance for footholds exactly step_width apart
        self.u_left = h.u_left
        self._plan = StepPlanner(sc, h, self.events)
        self.first = self._plan.first
        self._state = "standing"
        self._cmd = np.zeros(2)
        self._stop_requested = False
        self._last_vel = np.zeros(3)

    # ----------------------------------------------------------------- public state
    @property
    def state(self) -> str:
        """standing, starting, running, stopping or stopped."""
        end = self._plan.end
        if self._state == "stopping" and end is not None and self._i > end:
            return "stopped"
        if self._state == "starting" and self.takeoffs and self._i > self.takeoffs[0].index:
            return "running"
        return self._state

    @property
    def takeoffs(self) -> list[Takeoff]:
        """Every planned step (also those not emitted yet)."""
        return self._plan.takeoffs

    @property
    def step_count(self) -> int:
        """Number of take-offs emitted so far."""
        return sum(1 for tk in self.takeoffs if tk.index < self._i)

    @property
    def planned_velocity(self) -> FloatArray:
        """CoM velocity (3,) of the last emitted sample, m/s."""
        return self._last_vel.copy()

    @property
    def command_velocity(self) -> FloatArray:
        """The command in force (after the speed limits), (2,) m/s."""
        return self._cmd.copy()

    @property
    def horizons(self) -> VhipHorizons:
        """The fixed horizons of this run (weights, factorised eq. (13), prepared start/stop solvers)."""
        return self._h

    @property
    def start_solution(self) -> SwitchingSolution | None:
        """The solution of State Switching 1, once the start is planned."""
        return self._plan.start_solution

    @property
    def stop_solution(self) -> SwitchingSolution | None:
        """The solution of State Switching 3, once the stop is planned."""
        return self._plan.stop_solution

    def planned_com(self, index: int) -> FloatArray:
        """Planned horizontal CoM (2,) m at sample ``index`` (from the next sample on, within the
        plan's look-ahead), a copy."""
        out: FloatArray = self._plan.buf["c"][index].copy()
        return out

    # ----------------------------------------------------------------- inputs
    def command(self, vx: float, vy: float = 0.0) -> FloatArray:
        """Set the commanded speed, m/s. Returns the accepted command (clamped to max_speed).

        Raises:
            InputError: a non-finite value (the generator never produces NaN).
        """
        req = np.array([vx, vy], dtype=float)
        for k, name in enumerate(AXES):
            if not math.isfinite(req[k]):
                raise InputError(name, float(req[k]), "a finite speed in m/s")
        if self._stop_requested:
            for k, name in enumerate(AXES):
                if req[k] != self._cmd[k]:
                    self._event("ignored", name, req[k], self._cmd[k], "stop requested")
            return self._cmd.copy()
        vmax, why = self._speed_limit()
        acc: FloatArray = np.clip(req, -vmax, vmax)
        for k, name in enumerate(AXES):
            if acc[k] != req[k]:
                self._event("clamp_speed", name, req[k], acc[k], f"|v| <= {vmax[k]:.4g} ({why[k]})")
        self._cmd = acc
        return acc.copy()

    def _speed_limit(self) -> tuple[FloatArray, list[str]]:
        lim = self.sc.limits
        return speed_limit(
            np.asarray(lim.max_speed, float), lim.max_stride, self.n_step * self.dt, self.width, self.sc.foot.size[1]
        )

    @property
    def max_speed(self) -> FloatArray:
        """Largest sustainable |command| per axis, m/s: the scenario's max_speed, and the speeds at
        which the steady strides (x: v T_step; y: step_width +/- v T_step) stay within max_stride and
        keep the feet one foot width apart."""
        return self._speed_limit()[0]

    def stop(self) -> None:
        """Request the stop: the command ramps to zero, then State Switching 3 ends at rest."""
        if not self._stop_requested:
            self._stop_requested = True
            self._event("stop", "command", float(np.hypot(*self._cmd)), 0.0, "stop requested")
            self._cmd = np.zeros(2)

    # ----------------------------------------------------------------- planning
    def _plan_start(self) -> None:
        n = self._plan.start(self.t, self._run_command())
        self._state = "starting"
        self._next_plan = n

    def _run_command(self) -> FloatArray:
        """The command the next running step heads for (zero once the stop is requested)."""
        return np.zeros(2) if self._stop_requested else self._cmd

    def _plan_next(self) -> None:
        """At a take-off: plan the step after the next (running or the stop)."""
        end_prev = self._plan.buf.n - 1
        if self._stop_requested and np.all(np.abs(self._plan.last_cmd_target) < 1e-12):
            self._plan.stop()
            self._state = "stopping"
            self._next_plan = None
            return
        self._plan.run_step(self.t, self._run_command())
        self._next_plan = end_prev
        if self._state == "starting" and self._i > self.takeoffs[0].index:
            self._state = "running"

    # ----------------------------------------------------------------- re-planning
    def replan(self, com_pos: FloatArray, com_vel: FloatArray) -> None:
        """Re-plan from a measured CoM state at the time of the next sample (:attr:`t`).

        The committed footholds up to the next take-off are kept: the CoM is propagated from the
        measured (x, y) position and velocity with eq. (9') to that take-off, then the step after it
        is planned again by Algorithm 1 (new foothold, same take-off speed target unless the stride
        limits need a different one: then clamped within max_accel_per_step and reported). A swing
        foot already in the air is redirected from where it is, keeping its position, velocity and
        acceleration (:mod:`.swings`). Only while running.

        Raises:
            InputError: non-finite measurement. InfeasibleError: not running.
        """
        pos = np.asarray(com_pos, float).ravel()[:2]
        vel = np.asarray(com_vel, float).ravel()[:2]
        if not (np.all(np.isfinite(pos)) and np.all(np.isfinite(vel))):
            raise InputError("measured CoM state", [*pos, *vel], "finite numbers")
        if self.state != "running" or self._next_plan is None or self._i > self._next_plan:
            raise InfeasibleError(
                f"replan: only while running between the first take-off and the stop (state {self.state})"
            )
        offset, shift = self._plan.replan(self.t, pos, vel, self._i, self._next_plan)
        note = "requested = measured CoM offset from the plan, applied = foothold shift (m)"
        self._event("replan", "com", offset, shift, note)

    # ----------------------------------------------------------------- emission
    def _block(self, n: int) -> int:
        """Plan the start or the next step when due; the samples (1..n) up to the next planning instant."""
        if self._state == "standing":
            self._plan_start()
        if self._next_plan is not None and self._i == self._next_plan:
            self._plan_next()
        if self._next_plan is not None and self._next_plan > self._i:
            return min(n, self._next_plan - self._i)
        return n

    def _emit(self, m: int) -> Samples:
        """Samples ``i .. i+m-1`` of the plan (``i`` the next sample); releases the buffer and feet behind them."""
        plan, end = self._plan, self._i + m
        if plan.end is not None:
            hold_at_rest(plan.buf, end, plan.rest_zmp)
        out = emit_samples(plan.buf, plan.feet, self._i, m, self.dt, self.g, self._cmd, FORCE_EPS)
        plan.buf.release(end - 1)
        self._last_vel = out.com_vel[-1].copy()
        plan.feet.prune(end)
        return out

    def step(self) -> Samples:
        """Advance to the next planning instant (one running step; the whole stop once stopping)."""
        if self._state == "standing":
            self._plan_start()
        if self._next_plan is not None and self._i == self._next_plan:
            self._plan_next()
        if self._next_plan is not None:
            return self.advance(self._next_plan - self._i)
        assert self._plan.end is not None
        return self.advance(max(1, self._plan.end + 1 - self._i))

    # ----------------------------------------------------------------- output
    def trajectory(self) -> Trajectory:
        """Everything emitted so far as the standard :class:`~gaitshift.Trajectory` contract."""
        s = self.emitted()
        footholds = self._plan.footholds
        fs = np.array([[p[0], p[1], 0.0, 0.0] for p, _ in footholds])
        side = np.array([sd for _, sd in footholds], dtype=np.int8)
        emitted = [tk for tk in self.takeoffs if tk.index < self._i]
        meta = {
            "planner": "vhip",
            "gravity": self.g,
            "foot_size": list(self.sc.foot.size),
            "scenario": self.sc.name,
            "dt": self.dt,
            "step_period": self.n_step * self.dt,
            "stance": self.n_sup * self.dt,
            "lateral_oscillation": self.u_left,
            "step_width": self.width,
            "events": [e.as_dict() for e in self.events],
            "velocity_convention": "central difference; acceleration: second difference (eqs. 7-9)",
        }
        extras = {
            "takeoff_index": np.array([tk.index for tk in emitted], dtype=np.int64),
            "takeoff_target": np.array([tk.target for tk in emitted]).reshape(-1, 2),
            "foothold_iterations": np.array([tk.iterations for tk in emitted], dtype=np.int64).reshape(-1, 2),
        }
        return Trajectory(
            t=s.t,
            com_pos=s.com_pos,
            com_vel=s.com_vel,
            com_acc=s.com_acc,
            zmp=s.zmp,
            phase=s.phase,
            contact=s.contact,
            foot_pos=s.foot_pos,
            stiffness=s.stiffness,
            footsteps=fs,
            footstep_side=side,
            command_vel=s.command,
            heading=np.zeros(len(s.t)),
            foot_yaw=np.zeros((len(s.t), 2)),
            gait=np.where(standing_samples(s.phase), STAND, RUN).astype(np.int8),
            command_yaw_rate=np.where(np.isfinite(s.command[:, 0]), 0.0, np.nan),
            meta=meta,
            extras=extras,
        )


def run_commands(
    gen: VhipGenerator, commands: list[Command], stop_at: float, max_time: float = 3600.0
) -> VhipGenerator:
    """Drive ``gen`` with a scripted profile of (t, vx, vy) commands, request the stop at ``stop_at``
    and run until the generator is at rest (:meth:`CommandScript.run`). A command is applied at the
    first tick with t >= its time (commands already due are applied before the next tick)."""
    CommandScript(commands, stop_at).run(gen, max_time)
    return gen


def plan_scenario(sc: VhipScenario) -> Trajectory:
    """Run the scenario's scripted command profile through the online generator; the whole run
    (start, running, stop at rest) as the standard trajectory contract (meta.planner = "vhip")."""
    gen = VhipGenerator(sc)
    CommandScript.from_scenario(sc).run(gen)
    return gen.trajectory()
