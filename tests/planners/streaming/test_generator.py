"""The shared emission loop: ``advance`` stops at every planning instant the generator reports, emits
the samples in order, keeps them for the history only with ``keep_history``, and ``tick`` is one
sample; ``finished`` follows the ``stopped`` state; events are stamped with the time of the next
sample."""

import numpy as np
import pytest

from gaitshift.errors import InputError
from gaitshift.planners.streaming import generator
from gaitshift.planners.streaming.generator import StreamingGenerator
from gaitshift.planners.streaming.samples import Samples


class _Toy(StreamingGenerator):
    """Plans every ``period`` samples; the column ``x`` is the sample index."""

    def __init__(self, period: int, keep_history: bool = True):
        super().__init__(0.01, keep_history)
        self.period, self._next_plan, self.plans = period, 0, []

    @property
    def state(self):
        return "stopped" if self._i >= 20 else "running"

    def _block(self, n):
        if self._i == self._next_plan:
            self.plans.append(self._i)
            self._next_plan += self.period
        return min(n, self._next_plan - self._i)

    def _emit(self, m):
        idx = np.arange(self._i, self._i + m)
        return Samples(idx * self.dt, {"x": idx.astype(np.float64)}, np.zeros((m, 2)))

    def trajectory(self):
        raise NotImplementedError

    def clamp(self, requested, applied):
        self._event("clamp_speed", "command.vx", requested, applied, "limit")


def test_advance_plans_at_each_instant_and_emits_in_order():
    gen = _Toy(period=4)
    out = gen.advance(10)
    np.testing.assert_array_equal(out.x, np.arange(10.0))
    np.testing.assert_allclose(out.t, np.arange(10) * 0.01)
    assert gen.plans == [0, 4, 8] and gen.tick_index == 10 and gen.next_plan_index == 12
    assert len(gen.tick()) == 1 and not gen.finished
    np.testing.assert_array_equal(gen.emitted().x, np.arange(11.0))


def test_without_history_nothing_is_kept_and_bad_tick_counts_are_refused():
    gen = _Toy(period=3, keep_history=False)
    gen.advance(20)
    assert gen.finished
    with pytest.raises(InputError):
        gen.emitted()
    with pytest.raises(InputError):
        gen.advance(0)
    with pytest.raises(InputError):
        _Toy(period=3).emitted()  # nothing emitted yet


def test_events_carry_the_time_of_the_next_sample():
    gen = _Toy(period=5)
    gen.advance(3)
    gen.clamp(2.0, 1.0)
    ev = gen.events[-1]
    assert (ev.t, ev.kind, ev.requested, ev.applied) == (0.03, "clamp_speed", 2.0, 1.0)


def test_the_history_read_again_merges_only_its_last_chunk_and_goes_on_in_order(monkeypatch):
    """A closed loop emits one tick at a time and reads the history at every step: the blocks since the last
    full chunk are merged into one once read (never the whole run again), and what comes after joins in
    order; ``emitted(since)`` is the run from that sample on."""
    monkeypatch.setattr(generator, "CHUNK", 5)
    gen = _Toy(period=4)
    for _ in range(3):
        gen.tick()
    assert len(gen.history()) == 1
    for _ in range(9):
        gen.tick()
    blocks = gen.history()
    assert [len(b) for b in blocks] == [12]  # merged at one read: a chunk now, never copied again
    first = blocks[0]
    gen.advance(3)
    gen.tick()
    blocks = gen.history()
    assert blocks[0] is first and [len(b) for b in blocks] == [12, 4]
    np.testing.assert_array_equal(gen.emitted().x, np.arange(16.0))
    np.testing.assert_allclose(gen.emitted().t, np.arange(16) * 0.01)
    for since in (0, 7, 12, 15):
        np.testing.assert_array_equal(gen.emitted(since).x, np.arange(float(since), 16.0))
    with pytest.raises(InputError, match="from sample 16 on"):
        gen.emitted(16)
