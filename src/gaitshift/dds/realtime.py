"""Real time: the brain ticks when a state arrives, on the robot's clock, with a wall-clock deadline.

A brain that ticks on a grid of its own (tick ``k`` due at ``t0 + k dt`` on the wall clock) meets the
robot's states at whatever phase the two clocks happen to have: a state that arrives just after a due
time waits almost a period for the next, so its command reaches the motors two robot ticks after the
readings instead of one, and which of the two varies as the clocks drift (measured on the G1 tour, two
processes on this machine, 2026-11-29: 1 tick for 45 %, 2 ticks for 51 %; the controller can predict
across a known latency, not across one that flips). Ticking on the state's arrival gives every command the
same way to the motors: computed at once, it is applied at the robot's next tick (92 % of the ticks on the
same tour; the rest are ticks that overran). So::

    wait for a state of a new tick, at most ``deadline`` periods after the last tick started
    (and at least ``MIN_WAIT`` s, so that the receive thread can hand over what came during a long tick)
    a new state:   the controller ticks at its own time, the robot's clock:  t = (tick - tick_0) dt
    none came:     the safety checks the state held and the last command is written again, t = t_last + dt

A state is acted on when it comes, as the newest reading (age 0). A tick whose deadline passed (a state lost
or late) does not tick the controller: the robot holds the last command by itself, and a controller tick
on the held state would claim the next tick's time, which the late state then could not take (the clock
would stay a period ahead of the readings from then on). So the late state, when it comes, is acted on at
its own time; only the safety's clock may pass the same time twice. The brain's clock is the robot's, as in
lockstep (:mod:`gaitshift.dds.lockstep`): a simulated robot that runs slower than real time is followed, not
outrun. ``LowState_.tick`` counts control periods (Unitree's simulator bridge and :mod:`gaitshift.dds.robot`;
unverified on a real G1). A tick misses its deadline when it lasts longer than a period: its command comes
after the robot's next tick took the previous one.
"""

import time
from collections.abc import Callable

from gaitshift.dds.lockstep import ticks_from

__all__ = ["DEADLINE", "DEADLINE_RANGE", "MIN_WAIT", "ArrivalClock"]

#: s: the shortest wait for a state, also when the deadline has passed (a tick that overran)
MIN_WAIT = 3e-4
#: periods after a tick's start that the next one waits for a state, by default; the range allowed
DEADLINE = 1.5
DEADLINE_RANGE = (1.0, 10.0)


class ArrivalClock:
    """The real-time brain's clock (module docstring).

    Attributes:
        period: s, the control period. deadline: periods after a tick's start that the next one waits for
        a new state. t: s, the time of the last tick (None before the first); acted: of the last tick on a
        new state. start: perf_counter s when the last tick started.
    """

    def __init__(self, period: float, deadline: float) -> None:
        self.period, self.deadline = period, deadline
        self.t: float | None = None
        self.acted: float | None = None
        self.start = -1.0

    def wait(self, take: Callable[[], bool], wait: Callable[[float], object]) -> bool:
        """Wait for a state of a new tick (``take()``: True when one was taken; ``wait(s)``: block up to
        ``s`` s for data) until the deadline; True when one came. Starts the tick."""
        end = (time.perf_counter() if self.t is None else self.start) + self.deadline * self.period
        new = take()
        if not new:
            wait(max(end - time.perf_counter(), MIN_WAIT))
            new = take()
        while not new and time.perf_counter() < end:
            wait(end - time.perf_counter())
            new = take()
        self.start = time.perf_counter()
        return new

    def tick(self, new: bool, first: int, tick: int) -> float:
        """The time s of the tick just started: ``new``, a state of robot tick ``tick`` came (``first``: the
        first state's tick): its time, never before the last tick that acted on a new state; else (the
        deadline passed) a period after the last tick, on the state held."""
        if new:
            t = ticks_from(first, tick) * self.period
            if self.acted is not None and t <= self.acted:
                t = self.acted + self.period
            self.acted = t
        else:
            t = self.period if self.t is None else self.t + self.period
        self.t = t
        return t
