"""The real-time brain's clock (gaitshift.dds.realtime), without DDS: a tick on each state's arrival at the
state's own time on the robot's clock; a deadline that passes goes on a period on the state held, and the
late state then takes its own time (the clock does not stay a period ahead of the readings); the clock never
goes back before a state acted on; the robot's uint32 ticks wrap."""

import time

import pytest

from gaitshift.dds.realtime import MIN_WAIT, ArrivalClock

DT = 0.002


def test_each_new_state_is_acted_on_at_its_own_tick_on_the_robots_clock():
    clock = ArrivalClock(DT, 1.5)
    assert clock.tick(True, 10, 10) == 0.0
    assert clock.tick(True, 10, 11) == pytest.approx(DT)
    assert clock.tick(True, 10, 15) == pytest.approx(5 * DT)  # a tick that overran: the newest state's time


def test_a_deadline_goes_on_a_period_and_the_late_state_then_takes_its_own_time():
    clock = ArrivalClock(DT, 1.5)
    times = [clock.tick(True, 0, 0), clock.tick(False, 0, 0), clock.tick(True, 0, 1), clock.tick(True, 0, 2)]
    assert times == pytest.approx([0.0, DT, DT, 2 * DT])
    assert clock.acted == pytest.approx(2 * DT)


def test_the_clock_never_goes_back_before_a_state_it_acted_on():
    clock = ArrivalClock(DT, 1.5)
    clock.tick(True, 0, 5)
    assert clock.tick(True, 0, 4) == pytest.approx(6 * DT)  # an older state (reordered): a period on


def test_the_robots_ticks_wrap_at_32_bits():
    clock = ArrivalClock(DT, 1.5)
    assert clock.tick(True, 2**32 - 1, 1) == pytest.approx(2 * DT)


def test_wait_returns_on_a_state_and_after_the_deadline_without_one():
    asked: list[float] = []

    def wait(seconds):  # data "arrives" within half a millisecond, or the time asked runs out
        asked.append(seconds)
        time.sleep(min(seconds, 5e-4))

    # a deadline of 100 s: a loaded machine's late wake-ups cannot end this wait before the third take
    arrivals = iter([False, False, True])
    assert ArrivalClock(DT, 100 / DT).wait(lambda: next(arrivals), wait) is True
    assert len(asked) == 2
    clock = ArrivalClock(DT, 1.5)
    clock.wait(lambda: True, wait)
    clock.tick(True, 0, 0)
    asked.clear()
    assert clock.wait(lambda: False, wait) is False  # nothing came: the deadline ends the wait
    assert asked and max(asked) <= 1.5 * DT  # never asked to wait past the deadline
    clock.tick(False, 0, 0)
    time.sleep(2 * DT)  # a tick that overran its deadline still waits a little for the receive thread
    asked.clear()
    assert clock.wait(lambda: False, wait) is False
    assert asked[0] == MIN_WAIT
