"""The horizontal base position the controller acts on: the estimate's, without its correction kicks.

The state estimator's position moves in two ways: with its velocity, and by the corrections of its
measurements (:mod:`gaitshift.control.estimation.inekf`: each stance-sole correction moves the
position directly). On the G1 running, the corrections move it up to 9 mm in one tick (2 ms, i.e.
4.4 m/s against a run of 1.5 m/s) and, on average, 1-4 cm/s away from the integral of its own velocity
(docs/deploy.md, "The estimate's position, kicked by its corrections"). A controller that tracks a
plan's CoM position and velocity takes each kick for a tracking error: on the estimate's position the
G1's soak fell in its fourth or fifth running turn, on eq. (1) of the same estimate it held (the
measurements there). The controller therefore acts on a complementary filter of the two: the
estimate's velocity ``v`` integrated, pulled to the estimate's position ``p`` with the time constant
``tau``,

.. math::

    \\dot{\\bar p} = v + (p - \\bar p) / \\tau                                                       (1)

discretised over the time ``h`` between two frames as a prediction and a blend,
``p_bar <- p_bar + h v``, then ``p_bar <- p_bar + (h / tau) (p - p_bar)`` (``h <= tau``). In the
frequency domain ``p_bar`` is ``p`` through a first-order low-pass plus ``v``'s integral through the
complementary high-pass: a kick of ``p`` reaches ``p_bar`` spread over ``tau``, while a ``p`` that moves
with ``v`` is followed without lag (``p_bar = p``). ``tau = 0``: ``p_bar = p``. The vertical position,
the orientation and the velocities stay the estimate's; the estimate itself (logged, published,
scored) is unchanged.
"""

from __future__ import annotations

import numpy as np

from gaitshift.errors import number_in

__all__ = ["POSITION_TAU_RANGE", "PositionFilter"]

#: allowed time constant of eq. (1), s (0: off)
POSITION_TAU_RANGE = (0.0, 60.0)


class PositionFilter:
    """Eq. (1) of the module docstring on the horizontal position.

    Args:
        tau: the time constant, s (0: the estimate's position as it is).
    """

    def __init__(self, tau: float) -> None:
        self.tau = number_in("position_tau", tau, POSITION_TAU_RANGE, "s")
        self.p: np.ndarray | None = None  # (2,) m, p_bar; None until the first frame

    def reset(self, p: np.ndarray) -> None:
        """Start at the estimate's horizontal position ``p`` (2,) m."""
        self.p = np.array(p[:2], float)

    def step(self, p: np.ndarray, v: np.ndarray, h: float) -> np.ndarray:
        """``p_bar`` (2,) m after ``h`` s with the estimate's horizontal position ``p`` and velocity ``v``
        ((2,) m, m/s, at the end of the step); the estimate's position when off or not started."""
        if self.tau == 0.0 or self.p is None:
            self.reset(p)
            assert self.p is not None
            return self.p.copy()
        k = min(max(h, 0.0) / self.tau, 1.0)
        self.p += h * np.asarray(v[:2], float)
        self.p += k * (np.asarray(p[:2], float) - self.p)
        return self.p.copy()
