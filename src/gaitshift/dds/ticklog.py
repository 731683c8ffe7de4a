"""Every tick's duration and its statistics: the brain's real-time report.

A tick's duration is the wall time from the state taken to the command written (the state's
conversion, the safety machine, the controller's tick, the command's conversion and its CRC, the DDS
write). A deadline is missed when a tick lasts longer than a period (real time: its command comes after
the robot's next tick, :mod:`gaitshift.dds.realtime`). Ticks on which the controller re-planned are marked,
so that the planning's share shows apart.
"""

from dataclasses import dataclass

import numpy as np

__all__ = ["TickLog", "TickStats"]


@dataclass(frozen=True)
class TickStats:
    """Tick durations, ms (NaN without ticks).

    Attributes:
        ticks: ticks logged. p50, p99, p999, max: percentiles and the largest duration, ms.
        missed: ticks that missed their deadline. replans: ticks on which the controller re-planned;
        replan_p50, replan_max: their durations, ms; other_p50, other_max: the other locomotion
        ticks' durations, ms.
    """

    ticks: int
    p50: float
    p99: float
    p999: float
    max: float
    missed: int
    replans: int
    replan_p50: float
    replan_max: float
    other_p50: float
    other_max: float


def _pct(a: np.ndarray, q: float) -> float:
    return float(np.percentile(a, q)) if len(a) else float("nan")


class TickLog:
    """The durations (s) of the ticks, their kinds, the missed deadlines."""

    def __init__(self) -> None:
        self.durations: list[float] = []
        self.kinds: list[int] = []  # 0: safety phase, 1: locomotion, 2: locomotion with a re-plan
        self.missed = 0

    def add(self, duration: float, kind: int, missed: bool) -> None:
        """Log one tick of ``duration`` s; ``kind`` 0 (damping or stand-up), 1 (the controller ticked),
        2 (the controller re-planned); ``missed`` its deadline."""
        self.durations.append(duration)
        self.kinds.append(kind)
        self.missed += bool(missed)

    def stats(self) -> TickStats:
        """The statistics of the ticks logged so far, ms."""
        d = np.asarray(self.durations, float) * 1e3
        k = np.asarray(self.kinds, int)
        rep, other = d[k == 2], d[k == 1]
        return TickStats(
            ticks=len(d),
            p50=_pct(d, 50),
            p99=_pct(d, 99),
            p999=_pct(d, 99.9),
            max=float(d.max()) if len(d) else float("nan"),
            missed=self.missed,
            replans=len(rep),
            replan_p50=_pct(rep, 50),
            replan_max=float(rep.max()) if len(rep) else float("nan"),
            other_p50=_pct(other, 50),
            other_max=float(other.max()) if len(other) else float("nan"),
        )
