"""A live session: the simulated robot walked and run by key commands, paced to the wall clock.

The locomotion generator (:class:`~gaitshift.control.locomotion_driver.LocomotionDriver`, live mode)
drives the closed loop of :func:`gaitshift.sim.loop.simulate`; a tick hook (:class:`Session`) turns
key actions into commands, paces the run so that one simulated second takes one wall-clock second
(when ``realtime``), and reports a status line (gait, speed, heading, real-time factor) every half
second of simulated time. Actions come from a script (tokens with waits in simulated seconds) or
from a poll function (a keyboard). ``quit`` (or the end of the script) requests the stop; the run
ends once the robot stands at rest.

Key actions change the command by the one key table (:data:`gaitshift.scenario.commands.KEYS`, steps
:data:`~gaitshift.scenario.commands.LOCOMOTION_STEP`): ``up``/``down`` forward speed, ``left``/``right``
lateral speed, ``turn-left``/``turn-right`` yaw rate; ``stop`` and ``quit`` stop.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from gaitshift.control.locomotion_driver import LocomotionDriver
from gaitshift.scenario.commands import KEYS, LOCOMOTION_STEP, key_change
from gaitshift.sim.loop import TickHook
from gaitshift.sim.result import SimResult
from gaitshift.sim.scenario_run import simulate_scenario
from gaitshift.trajectory.window import index_at

__all__ = ["Session", "run_session"]

GAIT_NAMES = ("stand", "walk", "run")
#: simulated time between two status lines, s
STATUS_PERIOD = 0.5


@dataclass
class Session:
    """The tick hook of a live session (module docstring).

    Args:
        driver: the live locomotion driver.
        script: (action, seconds) pairs (:func:`gaitshift.scenario.commands.parse_script`), or None.
        poll: returns the actions typed since the last call (a keyboard), or None.
        realtime: pace the run to the wall clock.
        status: receives a status line every :data:`STATUS_PERIOD` s of simulated time.
    """

    driver: LocomotionDriver
    script: list[tuple[str, float]] | None = None
    poll: Callable[[], list[str]] | None = None
    realtime: bool = True
    status: Callable[[str], None] = print
    command: np.ndarray = field(default_factory=lambda: np.zeros(3))
    quitting: bool = False
    _due: float = 0.0
    _next_status: float = 0.0
    _wall0: float = field(default_factory=time.perf_counter)

    def apply(self, action: str, t: float) -> None:
        """One key action at plan time ``t`` (s)."""
        if action in KEYS:
            self.command = self.command + np.array(key_change(action, LOCOMOTION_STEP))
            self.driver.command(*self.command.tolist())
        elif action in ("stop", "quit") and not self.quitting:
            self.quitting = True
            self.driver.stop()
        self._echo(action, t)

    def set_command(self, vx: float, vy: float, yaw_rate: float, t: float) -> None:
        """An absolute command (m/s, m/s in the heading frame, rad/s) at plan time ``t`` (s): the
        browser's sliders (:mod:`gaitshift.sim.web`); ignored once the stop is requested."""
        if not self.quitting:
            self.command = np.array([vx, vy, yaw_rate], float)
            self.driver.command(vx, vy, yaw_rate)
        self._echo("web", t)

    def quit(self, t: float) -> None:
        """End the session at plan time ``t`` (s): stop at rest (the browser's *End run*)."""
        self.apply("quit", t)

    def _echo(self, action: str, t: float) -> None:
        self.status(
            f"{action:>10s}  t={t:7.2f} s  command=({self.command[0]:+.2f}, {self.command[1]:+.2f} m/s, "
            f"{self.command[2]:+.2f} rad/s)"
        )

    def _script_actions(self, t: float) -> None:
        assert self.script is not None
        while self.script and self._due <= t + 1e-9:
            action, sec = self.script.pop(0)
            if action == "wait":
                self._due += sec
            else:
                self.apply(action, t)
        if not self.script and not self.quitting:
            self.apply("quit", t)

    def __call__(self, k: int, t: float, d: Any) -> None:
        """The tick hook: actions, status, pacing."""
        if self.script is not None:
            self._script_actions(t)
        if self.poll is not None and k % 10 == 0:
            for action in self.poll():
                self.apply(action, t)
        if t >= self._next_status - 1e-9:
            self._next_status += STATUS_PERIOD
            self.status(self.line(t, d))
        if self.realtime:
            lag = t - (time.perf_counter() - self._wall0)
            if lag > 0:
                time.sleep(lag)

    def line(self, t: float, d: Any) -> str:
        """The status line: gait, measured CoM speed in the heading frame, heading, real-time factor."""
        gen = self.driver.gen
        tr = self.driver.trajectory
        i = index_at(tr, t)
        psi = float(tr.heading[i])
        v = d.subtree_linvel[0] if hasattr(d, "subtree_linvel") else np.zeros(3)
        vh = (math.cos(psi) * v[0] + math.sin(psi) * v[1], -math.sin(psi) * v[0] + math.cos(psi) * v[1])
        wall = time.perf_counter() - self._wall0
        rtf = t / wall if wall > 0 else math.nan
        return (
            f"t={t:7.2f} s  {GAIT_NAMES[int(tr.gait[i])]:5s}  speed=({vh[0]:+.2f}, {vh[1]:+.2f}) m/s  "
            f"heading={psi:+.2f} rad  real-time factor={rtf:.2f}  {gen.state}"
        )


def run_session(
    driver: LocomotionDriver, session: Session, viewer: bool, robot: Any = "g1", views: Sequence[TickHook] = ()
) -> SimResult:
    """Run the closed loop of a live session on ``robot`` (name, YAML or config) until the robot
    stands at rest after the stop; ``views`` are tick hooks called after the session's (a browser
    view, :mod:`gaitshift.sim.web`)."""
    hooks: list[TickHook] = [session, *views]
    run = simulate_scenario(driver.sc, robot, driver=driver, hooks=hooks, control_period=driver.gen.dt, viewer=viewer)
    return run.result
