"""The brain's side of the lockstep handshake (gaitshift.dds.lockstep), without DDS: it ticks once per robot
clock, only once it holds the state the clock names, never twice at one tick, and a state's age counts the
robot ticks since it was first named."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from gaitshift.dds.lockstep import LockstepClock, tick_after
from gaitshift.dds.own_messages import Clock_


class _Reader:
    """The clocks received since the last take."""

    def __init__(self) -> None:
        self.inbox: list[Clock_] = []

    def take(self, N: int) -> list[Clock_]:
        out, self.inbox = self.inbox[:N], self.inbox[N:]
        return out


def _clock() -> tuple[LockstepClock, _Reader]:
    clock = LockstepClock.__new__(LockstepClock)  # the handshake's rules, not the DDS reader
    reader = _Reader()
    clock.reader, clock.tick, clock.pending, clock.since, clock.named = reader, -1, None, 0, -1
    return clock, reader


@given(st.integers(0, 2**32 - 1), st.integers(1, 2**31 - 1))
def test_a_later_tick_is_after_across_the_wrap(a, d):
    """uint32 ticks: d ticks on is after, and not before, also where the count wraps."""
    later = (a + d) % 2**32
    assert tick_after(later, a) and tick_after(a, a) and not tick_after(a, later)


def test_the_brain_ticks_once_per_clock_on_the_state_it_names():
    clock, reader = _clock()
    reader.inbox = [Clock_(tick=5, state_tick=3)]
    assert clock.due(None) is None  # no state yet
    assert clock.due(2) is None  # an older state than the one named (DDS does not order two topics)
    assert clock.due(3) == 5 and clock.age(0.002) == 0.0
    reader.inbox = [Clock_(tick=5, state_tick=3)]  # the robot wrote it again (no command came yet)
    assert clock.due(3) is None
    reader.inbox = [Clock_(tick=6, state_tick=3)]  # a tick that released no state: the state held, a tick older
    assert clock.due(3) == 6 and clock.age(0.002) == 0.002
    reader.inbox = [Clock_(tick=7, state_tick=5)]  # the state of tick 4 was lost or overtaken
    assert clock.due(5) == 7 and clock.age(0.002) == 0.0
