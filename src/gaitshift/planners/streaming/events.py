"""What a streaming generator reports: events (clamps, ignored commands, re-plans) and planned steps.

Generic over the generator: an :class:`Event` names the field it concerns and the requested and
applied values; a :class:`Takeoff` is one planned step (its planning instant, target velocity and
foothold).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from gaitshift.models.arrays import FloatArray, IntArray

__all__ = ["Event", "Takeoff"]


@dataclass(frozen=True)
class Event:
    """Something the generator changed or refused: a clamp, an ignored command, a re-plan.

    Attributes:
        t: time of the event, s (rounded to 1e-9 s).
        kind: e.g. ``clamp_speed``, ``clamp_accel``, ``clamp_stride``, ``clamp_start``, ``ignored``,
            ``stop``, ``replan``.
        field: the input concerned, e.g. ``command.vx``.
        requested, applied: the value asked for and the value used (units of the field).
        note: why (the limit that applied).
    """

    t: float
    kind: str
    field: str
    requested: float
    applied: float
    note: str = ""

    @classmethod
    def at(cls, t: float, kind: str, field: str, requested: float, applied: float, note: str = "") -> Event:
        """An event at time ``t`` (rounded to 1e-9 s), values as floats."""
        return cls(round(t, 9), kind, field, float(requested), float(applied), note)

    def as_dict(self) -> dict[str, Any]:
        """The event as a JSON-ready dict."""
        return {
            "t": self.t,
            "kind": self.kind,
            "field": self.field,
            "requested": self.requested,
            "applied": self.applied,
            "note": self.note,
        }


@dataclass(frozen=True, eq=False)
class Takeoff:
    """One planned step: sample index and time (s) of its take-off, target take-off velocity (2,) m/s,
    foothold (2,) m, foothold iterations per axis (2,) and the kind (start, run, stop)."""

    index: int
    t: float
    target: FloatArray
    foothold: FloatArray
    iterations: IntArray
    kind: str
