"""Faults on the robot's link to the brain: state packets dropped, corrupted, delayed with jitter.

The robot process (:mod:`gaitshift.dds.robot`) hands each tick's ``LowState_`` to :class:`Link` instead of
writing it; the link decides, with its own seeded generator, what the brain gets and when::

    dropped    with probability drop:      never written
    corrupted  with probability corrupt:   written with its CRC off by one (the brain drops it and counts it)
    delay      d_k = delay + U(-jitter, jitter)   s, clipped at 0
    written    at the first tick j >= k with j dt >= k dt + d_k, and never before a state written earlier
               (the link keeps the order: a state is released at max(its own tick, the last release))

Delays act at the robot's ticks (``dt``, 2 ms): a state delayed 4 ± 1 ms is written 2 or 3 ticks after it
was taken (ceil), so the mean delay is between ``delay`` and ``delay + dt``. The release ticks are ticks of
the robot's own clock in real time and in lockstep alike, so that a lockstep run on a loaded machine sees
the same latency in simulated time as a real-time run on a fast one.

Only the states are faulted: the command path (``rt/lowcmd``) is the brain's own, and a lost command is
the robot's damping-after business. Everything the link did is counted (:class:`LinkCounts`).
"""

import math
from collections import deque
from dataclasses import dataclass
from typing import Any

import numpy as np

from gaitshift.errors import number_in

__all__ = ["Link", "LinkCounts", "LinkFaults"]


@dataclass(frozen=True)
class LinkFaults:
    """What the link does to the states (module docstring).

    Attributes:
        drop: probability that a state is never written, in [0, 1).
        corrupt: probability that a state is written with a wrong CRC, in [0, 1).
        delay: s added to every state, >= 0.
        jitter: s, half width of the uniform spread of the delay, <= delay.
        seed: the run's random seed: the link's faults, and the robot process's sensor noise (another stream).
    """

    drop: float = 0.0
    corrupt: float = 0.0
    delay: float = 0.0
    jitter: float = 0.0
    seed: int = 0

    def __post_init__(self) -> None:
        number_in("--drop", self.drop, (0.0, 0.5))
        number_in("--corrupt", self.corrupt, (0.0, 0.5))
        number_in("--delay-ms", 1e3 * self.delay, (0.0, 1000.0), "ms")
        number_in("--jitter-ms", 1e3 * self.jitter, (0.0, 1e3 * self.delay), "ms (at most --delay-ms)")
        number_in("--seed", self.seed, (0, 2**32 - 1))

    @property
    def clean(self) -> bool:
        """No fault: every state is written at its own tick, as it is."""
        return self.drop == self.corrupt == self.delay == 0.0


@dataclass
class LinkCounts:
    """What the link did: states taken, dropped, corrupted, written; the mean and max delay of the written
    ones in ticks (NaN when none was written)."""

    taken: int = 0
    dropped: int = 0
    corrupted: int = 0
    written: int = 0
    delay_ticks_total: int = 0
    delay_ticks_max: int = 0

    @property
    def delay_ticks_mean(self) -> float:
        return self.delay_ticks_total / self.written if self.written else math.nan


class Link:
    """The states in flight (module docstring).

    Args:
        faults: what the link does.
        dt: the robot's tick, s.
        corrupted: ``corrupted(state) -> state``: the message with its CRC off by one.
    """

    def __init__(self, faults: LinkFaults, dt: float, corrupted: Any) -> None:
        self.faults, self.dt, self.corrupted = faults, float(dt), corrupted
        self.rng = np.random.default_rng(faults.seed)
        self.queue: deque[tuple[int, int, Any, bool]] = deque()  # (release tick, taken tick, state, intact)
        self.last_release = -1
        self.counts = LinkCounts()

    def take(self, k: int, state: Any) -> None:
        """The state of tick ``k``: dropped, or queued for its release tick (corrupted or not)."""
        f, c = self.faults, self.counts
        c.taken += 1
        draw = self.rng.random(3)
        if draw[0] < f.drop:
            c.dropped += 1
            return
        intact = not draw[1] < f.corrupt
        if not intact:
            c.corrupted += 1
            state = self.corrupted(state)
        delay = max(f.delay + f.jitter * (2.0 * draw[2] - 1.0), 0.0)
        release = max(k + math.ceil(delay / self.dt - 1e-9), self.last_release)
        self.last_release = release
        self.queue.append((release, k, state, intact))

    def release(self, k: int) -> list[tuple[Any, bool]]:
        """The states due at tick ``k``, oldest first, each with whether its CRC is intact."""
        out, c = [], self.counts
        while self.queue and self.queue[0][0] <= k:
            _, taken, state, intact = self.queue.popleft()
            c.written += 1
            c.delay_ticks_total += k - taken
            c.delay_ticks_max = max(c.delay_ticks_max, k - taken)
            out.append((state, intact))
        return out
