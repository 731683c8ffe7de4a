"""The sample clock of a streaming generator (the online VHIP generator and the locomotion generator).

Samples are ``dt`` s apart; ``_i`` is the index of the next sample to emit and ``_next_plan`` the index
of the next planning instant (None when none is due: standing, or once the stop is planned).
"""

from __future__ import annotations

__all__ = ["SampleClock"]


class SampleClock:
    """Time, tick index and next planning instant of a streaming generator (module docstring)."""

    dt: float
    _i: int
    _next_plan: int | None

    @property
    def t(self) -> float:
        """Time of the next sample, s."""
        return self._i * self.dt

    @property
    def tick_index(self) -> int:
        """Index of the next sample to emit."""
        return self._i

    @property
    def next_plan_index(self) -> int | None:
        """Sample index of the next planning instant (None while none is due)."""
        return self._next_plan
