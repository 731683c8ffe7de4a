"""The brain's diagnostics: its state estimate on ``rt/gaitshift/estimate``
(:class:`~gaitshift.dds.own_messages.Estimate_`), for the robot process to score (:mod:`gaitshift.dds.scoring`).

Written every ``every`` ticks of the brain (every phase; the first tick included), after the tick's
command: the ``LowState_.tick`` the tick acted on, the machine's time and phase, and, on a tick where
the controller ticked (locomotion), the estimator's output of that tick (``Controller.record.estimate``:
the pelvis position and quaternion w x y z, its linear velocity, the fused contact flags), else
``valid = 0``. The brain only writes this topic: the truth never flows back to it.
"""

from typing import Any

import numpy as np

from gaitshift.dds.own_messages import ESTIMATE_TOPIC, Estimate_
from gaitshift.dds.transport import Endpoint, topic_writer
from gaitshift.errors import InputError

__all__ = ["Diagnostics", "estimate_message"]


def estimate_message(tick: int, t: float, phase: str, estimate: Any | None) -> Any:
    """The :class:`Estimate_` of LowState_ tick ``tick`` at ``t`` s in ``phase``; ``estimate`` an
    ``EstimateRecord`` (``qpos`` (nq,), ``qvel`` (nv,) with the floating base first, ``contact`` (2,)) or
    None (``valid = 0``)."""
    msg: Any = Estimate_(tick=int(tick) & 0xFFFFFFFF, t=float(t), phase=phase)
    if estimate is None:
        return msg
    qpos, qvel = np.asarray(estimate.qpos, float), np.asarray(estimate.qvel, float)
    msg.valid = 1
    msg.base_pos = [float(v) for v in qpos[:3]]
    msg.base_quat = [float(v) for v in qpos[3:7]]
    msg.base_vel = [float(v) for v in qvel[:3]]
    msg.contact = [int(bool(c)) for c in np.asarray(estimate.contact)[:2]]
    return msg


class Diagnostics:
    """The brain's writer of ``rt/gaitshift/estimate`` (module docstring).

    Args:
        endpoint: the brain's endpoint (its participant). every: write every ``every``-th tick (>= 1).

    Attributes:
        ticks: ticks seen. written: estimates written (``valid`` or not).
    """

    def __init__(self, endpoint: Endpoint, every: int) -> None:
        if isinstance(every, bool) or not isinstance(every, int) or every < 1:
            raise InputError("--diag-every", every, "an integer >= 1 (0: no diagnostics)")
        self.writer = topic_writer(endpoint, ESTIMATE_TOPIC, Estimate_)
        self.every = every
        self.ticks = self.written = 0

    def publish(self, tick: int, t: float, phase: str, estimate: Any | None) -> None:
        """The tick's estimate (:func:`estimate_message`), when this tick is one of every ``every``."""
        self.ticks += 1
        if (self.ticks - 1) % self.every:
            return
        self.writer.write(estimate_message(tick, t, phase, estimate))
        self.written += 1
