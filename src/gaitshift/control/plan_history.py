"""The run's plan as the loop tracked it, from the windows a live driver handed it.

A live plan comes as windows (:mod:`gaitshift.trajectory.window`): each re-plan's samples from a second
before it to the end of its look-ahead. The loop tracks plan ``k`` from the tick that adopted it, ``a_k``,
to the tick that adopted the next, so the run's plan is

.. math::

    \\mathrm{plan} = P_0[a_0, a_1) \\,\\Vert\\, P_1[a_1, a_2) \\,\\Vert \\cdots \\Vert\\, P_K[a_K, \\mathrm{end}]   (1)

(``[a, b)`` the run's samples ``a`` to ``b - 1``). With scripted commands and no re-plan from the
measurement (the default), each ``P_k`` agrees with the generator's later output up to its end, so (1) is
the plan the generator emitted. A piece is copied when the next plan comes (a few hundred samples), so
the history costs the tick nothing that grows with the run; :meth:`PlanHistory.whole` puts it together
when asked (the run's metrics, its saved plan).
"""

from __future__ import annotations

import numpy as np

from gaitshift.trajectory.contract import Trajectory
from gaitshift.trajectory.window import cut, first_index, join

__all__ = ["PlanHistory"]


class PlanHistory:
    """Eq. (1) of the module docstring.

    Args:
        plan: the plan the run starts on (tracked from its first sample).
    """

    def __init__(self, plan: Trajectory) -> None:
        self.cuts: list[dict[str, np.ndarray]] = []
        self.plan, self.start = plan, first_index(plan)

    def adopt(self, plan: Trajectory, at: int) -> None:
        """``plan`` is tracked from the run's sample ``at`` on (from the last plan's end, when that came
        first: a late plan takes over from where the last one stopped)."""
        end = first_index(self.plan) + len(self.plan)
        at = max(min(at, end), self.start, first_index(plan))
        self.cuts.append(cut(self.plan, self.start, at))
        self.plan, self.start = plan, at

    def whole(self) -> Trajectory:
        """The run's plan, eq. (1)."""
        return join(self.cuts, self.plan, self.start)
