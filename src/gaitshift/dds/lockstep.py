"""Lockstep: the brain ticks once per robot tick, as it would in real time, however long each tick takes.

In real time the brain ticks every period on the newest state it holds: on a link that delays the states
by a varying time, some ticks find no new state (the brain ticks on the one it holds, a period older)
and some find two (it takes the newer). Lockstep must do the same, or a lockstep run is not the run a
real-time brain would make. So the robot process, in lockstep, writes a :class:`Clock_` at each of its
ticks, once it has written a first intact state::

    robot  tick k:  release the link's states (the newest intact one written)
                    write Clock_(tick = k, state_tick = the newest intact state written so far)
                    wait for one command; apply it; step
    brain          wait for a Clock_ of a new tick, then for the state it names (DDS does not order two
                   topics); tick at the robot's time k on the newest state held; write the command

The state's age at tick ``k`` is ``(k - k_s) dt``, ``k_s`` the robot tick at which the state held was
first named (0 for a state written at the tick it was taken): the time since it arrived, on the robot's
clock, what the real-time brain measures on the wall clock. A robot that writes no clock (none came
within the stale limit) is a silent robot: the brain's stale-state fault.

The brain's side is :class:`LockstepClock`; the robot's is a writer of :data:`CLOCK_TOPIC`
(:mod:`gaitshift.dds.robot`).
"""

from typing import Any

from cyclonedds.core import InstanceState, ReadCondition, SampleState, ViewState

from gaitshift.dds.own_messages import CLOCK_TOPIC, Clock_
from gaitshift.dds.transport import Endpoint, topic_reader

__all__ = ["LockstepClock", "tick_after", "ticks_from"]

#: ticks are uint32 and wrap
_WRAP = 2**32


def ticks_from(b: int, a: int) -> int:
    """The ticks from tick ``b`` to tick ``a`` (uint32 ticks, wrapping), >= 0."""
    return (a - b) % _WRAP


def tick_after(a: int, b: int) -> bool:
    """Tick ``a`` is ``b`` or later (uint32 ticks, wrapping)."""
    return ticks_from(b, a) < _WRAP // 2


class LockstepClock:
    """The brain's reader of the robot's clock (module docstring), attached to the endpoint's wait set so
    that a clock wakes the brain as a state does.

    Attributes:
        tick: the robot tick the brain last ticked at (-1: none yet).
        pending: the newest clock not yet ticked at, or None.
        since: the robot tick at which the state named last first came.
        named: the ``state_tick`` of the newest clock seen (-1: none yet).
    """

    def __init__(self, endpoint: Endpoint) -> None:
        self.reader: Any = topic_reader(endpoint, CLOCK_TOPIC, Clock_)
        self.condition = ReadCondition(self.reader, ViewState.Any | InstanceState.Any | SampleState.NotRead)
        endpoint.waitset.attach(self.condition)
        self.tick = -1
        self.pending: Clock_ | None = None
        self.since = 0
        self.named = -1

    def take(self) -> None:
        """Take the clocks received; keep the newest of a tick not yet ticked at (a repeat is dropped)."""
        for msg in self.reader.take(N=64):
            if not isinstance(msg, Clock_) or (self.tick >= 0 and not tick_after(msg.tick, self.tick + 1)):
                continue
            if self.pending is None or tick_after(msg.tick, self.pending.tick):
                self.pending = msg

    def due(self, state_tick: int | None) -> int | None:
        """The robot tick to tick at now, or None: a clock of a new tick came and the brain holds the state
        it names (``state_tick``: the tick of the newest state held, None: none). Marks it ticked."""
        self.take()
        clock = self.pending
        if clock is None or state_tick is None or not tick_after(state_tick, clock.state_tick):
            return None
        if clock.state_tick != self.named:
            self.named, self.since = clock.state_tick, clock.tick
        self.pending, self.tick = None, clock.tick
        return int(clock.tick)

    def age(self, period: float) -> float:
        """The held state's age at the tick last ticked at, s (module docstring)."""
        return ticks_from(self.since, self.tick) * period
