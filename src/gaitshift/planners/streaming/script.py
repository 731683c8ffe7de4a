"""A scripted speed profile for a streaming generator: timed (vx, vy) commands and a stop request.

:class:`CommandScript` drives any generator with the streaming interface of :class:`Streaming`
(:class:`~gaitshift.planners.vhip.generator.VhipGenerator` and
:class:`~gaitshift.planners.locomotion.generator.LocomotionGenerator`):
it applies each command at the first control tick at or after its time, requests the stop at the
first tick at or after ``stop_at``, and tells the driver when the next scripted event is due, so a
driver can advance in whole blocks between events instead of tick by tick. Typical uses::

    script = CommandScript.from_scenario(sc)
    script.run(gen)                      # the whole run, until the generator is at rest

    script.advance_to(gen, index)        # a closed loop: follow simulated time to tick ``index``
    rest = script.remaining()            # the commands not applied yet, for a copy of the generator
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from typing import Any, Protocol

from gaitshift.errors import InfeasibleError

__all__ = ["Command", "CommandScript", "ScriptedScenario", "Streaming", "TimedCommand"]

#: one scripted event: (time s, *payload), e.g. (t, vx, vy); the payload goes to the script's ``apply``
Command = tuple[Any, ...]


class TimedCommand(Protocol):
    """A scenario's command: time ``t`` (s) and speeds ``vx``, ``vy`` (m/s)."""

    @property
    def t(self) -> float: ...
    @property
    def vx(self) -> float: ...
    @property
    def vy(self) -> float: ...


class ScriptedScenario(Protocol):
    """A scenario with a command profile and an optional stop time (s)."""

    @property
    def commands(self) -> Sequence[TimedCommand]: ...
    @property
    def stop_at(self) -> float | None: ...


class Streaming(Protocol):
    """What :class:`CommandScript` needs of a generator: the time of the next sample ``t`` (s), the
    sample step ``dt`` (s), the index of the next sample ``tick_index``, ``finished`` once at rest
    after the stop, and the inputs ``command(vx, vy)``, ``stop()``, ``advance(n)`` (n ticks) and
    ``step()`` (to the next planning instant)."""

    @property
    def t(self) -> float: ...
    @property
    def dt(self) -> float: ...
    @property
    def tick_index(self) -> int: ...
    @property
    def finished(self) -> bool: ...
    def command(self, vx: float, vy: float = ...) -> object: ...
    def stop(self) -> None: ...
    def advance(self, n: int) -> object: ...
    def step(self) -> object: ...


def _command(gen: Streaming, *payload: Any) -> object:
    """The default action: ``gen.command(*payload)``."""
    return gen.command(*payload)


class CommandScript:
    """Timed speed commands and a stop time, applied to a streaming generator as its time passes.

    Args:
        commands: (t, *payload), e.g. (t, vx, vy) in s, m/s, m/s; any order (applied in time order,
            equal times in the given order).
        stop_at: time of the stop request, s.
        apply: ``apply(gen, *payload)`` applies one command; by default ``gen.command(*payload)``.

    A command (or the stop) is due at the first tick whose time ``gen.t`` is at or after its time,
    within :attr:`TOL`. The script remembers what it has applied, so one script drives one generator.
    """

    #: a scripted time counts as reached when ``gen.t + TOL >= t``, s
    TOL = 1e-12

    def __init__(self, commands: Iterable[Command], stop_at: float, apply: Callable[..., object] | None = None):
        self._events: tuple[Command, ...] = tuple(sorted(((float(c[0]), *c[1:]) for c in commands), key=lambda c: c[0]))
        self.stop_at = float(stop_at)
        self._apply = apply if apply is not None else _command
        self._next = 0  # index of the first command not applied yet
        self._stopped = False

    @classmethod
    def from_scenario(cls, sc: ScriptedScenario) -> CommandScript:
        """The script of a scenario's ``commands`` and ``stop_at`` (None: 2 s after the last command)."""
        cmds = [(c.t, c.vx, c.vy) for c in sc.commands]
        return cls(cmds, sc.stop_at if sc.stop_at is not None else max(c[0] for c in cmds) + 2.0)

    @property
    def commands(self) -> tuple[Command, ...]:
        """All scripted commands, in time order."""
        return self._events

    @property
    def pending(self) -> tuple[Command, ...]:
        """The commands not applied yet, in time order."""
        return self._events[self._next :]

    @property
    def stop_requested(self) -> bool:
        """True once the script has requested the stop."""
        return self._stopped

    def apply_due(self, gen: Streaming) -> None:
        """Apply every command due at the generator's current time ``gen.t`` (in time order), then
        request the stop if it is due."""
        t = gen.t + self.TOL
        while self._next < len(self._events) and self._events[self._next][0] <= t:
            self._apply(gen, *self._events[self._next][1:])
            self._next += 1
        if not self._stopped and self.stop_at <= t:
            gen.stop()
            self._stopped = True

    def next_time(self) -> float:
        """Time of the next scripted event, s: the next pending command or, until it is requested, the
        stop; ``math.inf`` when nothing is left."""
        nxt = self._events[self._next][0] if self._next < len(self._events) else math.inf
        return nxt if self._stopped else min(nxt, self.stop_at)

    def next_tick(self, gen: Streaming) -> int | None:
        """Index of the first tick at or after :meth:`next_time` (at least the tick after the next
        sample), or None when nothing is left."""
        nxt = self.next_time()
        if not math.isfinite(nxt):
            return None
        return max(gen.tick_index + 1, math.ceil(nxt / gen.dt - 1e-9))

    def advance_to(self, gen: Streaming, index: int) -> None:
        """Advance ``gen`` to tick ``index`` (or until it is finished), in blocks between the scripted
        events, applying each when it is due."""
        while gen.tick_index < index and not gen.finished:
            nxt = self.next_tick(gen)
            target = index if nxt is None else min(index, nxt)
            gen.advance(target - gen.tick_index)
            self.apply_due(gen)

    def run(self, gen: Streaming, max_time: float = 3600.0) -> None:
        """Run ``gen`` through the whole script until it is at rest after the stop (after the stop
        request one planning step at a time).

        Raises:
            InfeasibleError: the generator did not stop within ``max_time`` s.
        """
        while True:
            self.apply_due(gen)
            if gen.finished:
                return
            if gen.t > max_time:
                raise InfeasibleError(f"the scripted run did not stop within {max_time} s")
            if self._stopped:
                gen.step()
                continue
            nxt = self.next_tick(gen)
            assert nxt is not None  # the stop is still ahead
            gen.advance(nxt - gen.tick_index)

    def remaining(self) -> CommandScript:
        """A new script of the pending commands and the same stop time (e.g. to finish a copy of the
        generator without touching this script)."""
        return CommandScript(self.pending, self.stop_at, self._apply)
