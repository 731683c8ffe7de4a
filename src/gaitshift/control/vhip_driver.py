"""Closed-loop driver of the online VHIP generator (paper 003): re-plan every step from the measured CoM.

The scenario's scripted speed commands are fed to a live
:class:`~gaitshift.planners.vhip.generator.VhipGenerator` as simulated time passes. At every
planning instant (the take-off that plans the next step) the generator re-plans from the **measured**
CoM position and velocity (``VhipGenerator.replan``: the committed footholds are kept, the next
foothold is chosen again by Algorithm 1 of paper 003), so drift is corrected by footholds as the paper
intends. The remainder of the run is then generated on a copy of the generator, which gives the loop
its look-ahead (swing targets, contact schedule).
"""

from __future__ import annotations

import copy
from typing import Any

import numpy as np

from gaitshift.planners.streaming.script import CommandScript
from gaitshift.planners.vhip.generator import VhipGenerator
from gaitshift.trajectory.contract import Trajectory


class VhipDriver:
    """Drive an :class:`VhipGenerator` through a closed-loop run (see module docstring).

    Args:
        scenario: an online (``vhip``) scenario with its scripted ``commands`` and ``stop_at``.

    Attributes:
        trajectory: the plan as last generated (initially from the scripted commands alone).
        replans: how many re-plans from a measured state were made.
    """

    def __init__(self, scenario: Any) -> None:
        self.sc = scenario
        self.gen = VhipGenerator(scenario)
        self.script = CommandScript.from_scenario(scenario)
        self._done: set[int] = set()
        self.replans = 0
        self.script.apply_due(self.gen)
        self.trajectory = self._finish_copy()
        self.duration_bound = float(self.trajectory.t[-1]) + 2.0
        self.step_feedback = False  # the generator re-plans its footholds from the measured CoM

    def _finish_copy(self) -> Trajectory:
        """The rest of the run on a copy of the generator: the loop's look-ahead."""
        g2 = copy.deepcopy(self.gen)
        self.script.remaining().run(g2)
        return g2.trajectory()

    def maybe_replan(self, t: float, com: np.ndarray, com_vel: np.ndarray) -> Trajectory | None:
        """Re-plan at the planning instant that ``t`` (s) reaches from the measured CoM position and
        velocity ((3,) m, m/s; the horizontal parts are used); returns the new plan or None."""
        g = self.gen
        idx = round(t / g.dt)
        if abs(idx * g.dt - t) > 1e-9:
            return None
        self.script.advance_to(g, idx)  # the live generator follows simulated time
        nxt = g.next_plan_index
        if nxt is None or nxt in self._done or g.tick_index != nxt or g.state != "running":
            return None
        g.replan(np.asarray(com)[:2], np.asarray(com_vel)[:2])
        self._done.add(nxt)
        self.replans += 1
        tr = self._finish_copy()
        # the sample at the re-plan joins the old plan (before) and the new one (from the measured
        # position on): its central-difference velocity mixes both, so take the new plan's forward
        # difference there (a take-off sample: flight, no CoM task uses it, only logs and figures)
        if 0 <= idx < len(tr) - 1:
            tr.com_vel[idx] = (tr.com_pos[idx + 1] - tr.com_pos[idx]) / tr.dt
        self.trajectory = tr
        return tr
