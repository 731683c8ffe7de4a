"""The skeleton both streaming generators share: emission in blocks, the history, events.

A streaming generator plans ahead of what it emits. :meth:`StreamingGenerator.advance` alternates
two steps until ``n`` samples are out: :meth:`~StreamingGenerator._block` plans whatever is due at
the next sample and says how many samples can be emitted before the next planning instant, then
:meth:`~StreamingGenerator._emit` produces them; the clock (:class:`~.clock.SampleClock`) moves on
and, with ``keep_history``, the block is kept for :meth:`~StreamingGenerator.emitted` (the run so
far, from which each generator builds its trajectory file).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from numbers import Integral

from gaitshift.errors import InputError
from gaitshift.planners.streaming.clock import SampleClock
from gaitshift.planners.streaming.events import Event
from gaitshift.planners.streaming.samples import Samples
from gaitshift.trajectory.contract import Trajectory

__all__ = ["MAX_TICKS", "StreamingGenerator"]

#: most control ticks one :meth:`StreamingGenerator.advance` call emits (1000 s at 1 ms)
MAX_TICKS = 1_000_000
#: samples a merged block of the history holds before the next one starts: a merge copies at most this
#: many and what came since, never the whole run (8 s at 2 ms)
CHUNK = 4096


class StreamingGenerator(SampleClock, ABC):
    """Block emission, history and events of a streaming generator (module docstring).

    Attributes:
        keep_history: keep the emitted blocks (False: memory stays bounded, no :meth:`trajectory`).
        events: what the generator changed or refused, in time order.
    """

    def __init__(self, dt: float, keep_history: bool) -> None:
        """A generator at its first sample, none planned yet; ``dt`` the sample step, s."""
        self.dt = dt
        self.keep_history = keep_history
        self.events: list[Event] = []
        self._i = 0
        self._next_plan: int | None = None
        self._blocks: list[Samples] = []
        self._chunks = 0  # the leading blocks of the history that are full chunks (:data:`CHUNK`)

    @property
    @abstractmethod
    def state(self) -> str:
        """The generator's state; ``stopped`` once at rest after the stop."""

    @property
    def finished(self) -> bool:
        """True once the stop is complete and the robot stands at rest."""
        return self.state == "stopped"

    @abstractmethod
    def _block(self, n: int) -> int:
        """Plan what is due at the next sample; the number of samples (1..n) to emit now."""

    @abstractmethod
    def _emit(self, m: int) -> Samples:
        """The next ``m`` samples (the clock has not moved yet)."""

    @abstractmethod
    def trajectory(self) -> Trajectory:
        """Everything emitted so far as the standard trajectory contract."""

    def _event(self, kind: str, fld: str, requested: float, applied: float, note: str = "") -> None:
        """Report an event at the time of the next sample (units of the field)."""
        self.events.append(Event.at(self.t, kind, fld, requested, applied, note))

    def advance(self, n: int) -> Samples:
        """Advance ``n`` control ticks (``n * dt`` s), planning on the way; returns their samples.

        Raises:
            InputError: ``n`` not an integer in [1, :data:`MAX_TICKS`].
        """
        if isinstance(n, bool) or not isinstance(n, Integral) or not 1 <= n <= MAX_TICKS:
            raise InputError("ticks", n, f"an integer in [1, {MAX_TICKS:,}] (call again for more)")
        n = int(n)
        blocks = []
        while n > 0:
            m = self._block(n)
            out = self._emit(m)
            self._i += m
            if self.keep_history:
                self._blocks.append(out)
            blocks.append(out)
            n -= m
        return Samples.concat(blocks)

    def tick(self) -> Samples:
        """Advance one control period (dt); returns that one sample."""
        return self.advance(1)

    def emitted(self, since: int = 0) -> Samples:
        """The samples emitted so far from sample number ``since`` on (0: every one), as one block.

        Raises:
            InputError: the history is not kept, or nothing was emitted since ``since``.
        """
        if not self.keep_history:
            raise InputError("keep_history", False, "True to collect the trajectory")
        out, start = [], 0
        for b in self.history():
            if start + len(b) > since:
                out.append(b if start >= since else b.tail(since - start))
            start += len(b)
        if not out:
            raise InputError("trajectory", "empty", f"at least one sample emitted from sample {since} on")
        return Samples.concat(out)

    def history(self) -> list[Samples]:
        """The kept blocks: full chunks of :data:`CHUNK` samples or more, then the rest merged into one (a
        merge copies the last chunk and what came since, instead of gathering every one-tick block of the
        run again: a closed loop's look-ahead reads the history at every step)."""
        blocks = self._blocks
        if len(blocks) - self._chunks > 1:
            blocks[self._chunks :] = [Samples.concat(blocks[self._chunks :])]
        if blocks and len(blocks[-1]) >= CHUNK:
            self._chunks = len(blocks)
        return blocks
