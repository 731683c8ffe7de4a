"""The brain's tick log (``gaitshift.dds.ticklog``) reports the percentiles of the durations in ms, counts
the missed deadlines, and shows the controller's re-plan ticks apart from its other ticks."""

import math

import pytest

from gaitshift.dds.ticklog import TickLog


def test_percentiles_misses_and_replans_apart():
    """1000 ticks of 1 ms with 10 of 3 ms (missed) of which 2 re-plans of 20 ms: p50 1 ms, max 20 ms, 10
    missed, the re-plans' and the other controller ticks' medians apart."""
    log = TickLog()
    for i in range(1000):
        if i in (100, 200):
            log.add(0.020, 2, True)
        elif i % 100 == 50:
            log.add(0.003, 1, True)
        else:
            log.add(0.001, 0 if i < 10 else 1, False)
    s = log.stats()
    assert s.ticks == 1000 and s.missed == 12 and s.replans == 2
    assert s.p50 == pytest.approx(1.0) and s.max == pytest.approx(20.0)
    assert s.p999 == pytest.approx(20.0, rel=0.05) and s.p99 == pytest.approx(3.0)
    assert s.replan_p50 == pytest.approx(20.0) and s.other_p50 == pytest.approx(1.0) and s.other_max == 3.0


def test_an_empty_log_is_nan():
    """No tick: NaN percentiles (written as null in --json), nothing missed."""
    s = TickLog().stats()
    assert s.ticks == 0 and s.missed == 0 and math.isnan(s.p50) and math.isnan(s.replan_max)
