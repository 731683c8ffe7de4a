"""The robot's link faults (:mod:`gaitshift.dds.link`): the drop and corruption rates are the asked ones
within their binomial spread, a corrupted state fails its CRC while the intact ones pass, every state is
written at the first tick at or after its delay, never before a state taken earlier, and the delay stays
inside delay +- jitter (plus one tick of rounding up); the same seed gives the same faults."""

import math

import numpy as np
import pytest

from gaitshift.control.frames import SensorFrame
from gaitshift.dds.convert import lowstate_from_frame
from gaitshift.dds.crc import lowstate_crc
from gaitshift.dds.link import Link, LinkFaults
from gaitshift.dds.robot import corrupted
from gaitshift.errors import InputError

DT = 0.002


def _state(k: int):
    n = 29
    frame = SensorFrame(
        t=k * DT, imu_quat=np.array([1.0, 0, 0, 0]), imu_gyro=np.zeros(3), imu_acc=np.array([0, 0, 9.81]),
        q=np.zeros(n), dq=np.zeros(n), tau_est=np.zeros(n),
    )  # fmt: skip
    return lowstate_from_frame(frame, k, 0)


def _run(faults: LinkFaults, ticks: int, make=lambda k: k):
    link, out = Link(faults, DT, lambda s: ("bad", s)), []
    for k in range(ticks):
        link.take(k, make(k))
        out += [(k, s, intact) for s, intact in link.release(k)]
    return link, out


def test_drop_and_corrupt_rates_are_the_asked_ones():
    n = 20000
    link, out = _run(LinkFaults(drop=0.05, corrupt=0.02, seed=3), n)
    c = link.counts
    for count, p in ((c.dropped, 0.05), (c.corrupted, 0.02 * 0.95)):
        assert abs(count - n * p) < 4 * math.sqrt(n * p * (1 - p))
    assert c.written == len(out) == n - c.dropped
    assert sum(not intact for *_, intact in out) == c.corrupted
    assert all(isinstance(s, tuple) for *_, s, intact in out if not intact)  # the corrupted copy was written


def test_a_corrupted_state_fails_its_crc_and_the_original_is_untouched():
    state = _state(7)
    bad = corrupted(state)
    assert bad.crc != lowstate_crc(bad) and state.crc == lowstate_crc(state)


def test_states_are_released_in_order_at_the_first_tick_after_their_delay():
    delay, jitter = 0.004, 0.001
    link, out = _run(LinkFaults(delay=delay, jitter=jitter, seed=1), 5000)
    released = np.array([k for k, _, _ in out])
    taken = np.array([s for _, s, _ in out])
    assert np.array_equal(taken, np.arange(len(taken)))  # in order, none lost
    lag = released - taken
    assert lag.min() >= math.floor((delay - jitter) / DT) and lag.max() <= math.ceil((delay + jitter) / DT) + 1
    assert np.all(np.diff(released) >= 0)
    assert set(lag) >= {2, 3}  # the jitter spreads the delay over the ticks it spans
    assert link.counts.delay_ticks_mean == pytest.approx(lag.mean())


def test_no_fault_writes_each_state_at_its_own_tick_and_a_seed_repeats():
    _, out = _run(LinkFaults(), 100)
    assert [(k, s) for k, s, _ in out] == [(k, k) for k in range(100)]
    a = _run(LinkFaults(drop=0.1, delay=0.003, jitter=0.002, seed=9), 500)[1]
    b = _run(LinkFaults(drop=0.1, delay=0.003, jitter=0.002, seed=9), 500)[1]
    assert a == b


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [({"drop": 0.9}, "--drop"), ({"corrupt": -0.1}, "--corrupt"), ({"delay": 0.001, "jitter": 0.002}, "--jitter-ms")],
)
def test_bad_faults_are_refused_naming_the_flag(kwargs, field):
    with pytest.raises(InputError, match=field):
        LinkFaults(**kwargs)
