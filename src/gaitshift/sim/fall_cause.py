"""Why a robot fell, classified from the run's log: crossing, slip, estimate, torque or reach.

The log of a fallen run (:mod:`gaitshift.sim.log`, the truth and the controller's estimate per tick)
is read over the window ``[t_fall - WINDOW, t_fall - LEAD]`` s before the fall (the last ``LEAD`` s
are the collapse itself, where everything goes wrong at once). The first rule that holds names the
cause:

1. ``crossing``: the legs touched each other or the feet's footprints overlapped
   (``legs_touch`` / ``feet_overlap``, :mod:`gaitshift.sim.leg_clearance`), anywhere in
   ``[t_fall - WINDOW, t_fall]``.
2. ``slip``: a sole on the floor (the truth's ``contact``) moved faster than :data:`SLIP_SPEED` m/s
   horizontally for :data:`SLIP_TIME` s in a row:

   .. math:: \\lVert \\dot p_{xy} \\rVert = \\lVert p_{xy}[k+1] - p_{xy}[k] \\rVert / \\Delta t > v_{slip}

3. ``estimate``: the controller's estimate was wrong: its base tilt off the truth's by more than
   :data:`TILT_ERROR` rad (the vertical as the two base frames see it,
   :func:`gaitshift.common.rotations.tilt_error`), or its horizontal base velocity off
   by more than :data:`VELOCITY_ERROR` m/s, or its fused contact wrong on a sole for
   :data:`CONTACT_TIME` s in a row.
4. ``torque``: a motor's command was at :data:`SATURATION` of its limit or more for
   :data:`SATURATION_TIME` s in a row.
5. ``reach``: none of the above: the robot sensed, gripped and actuated as asked, and its steps
   could not reach a place that recovers it (the push or the speed beyond what its step limits
   catch).

The thresholds are engineering choices (documented in docs/robustness.md with how they split the map's
falls), not physics: the classification names the first suspect, and the logs stay for a look.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gaitshift.common.rotations import tilt_error
from gaitshift.common.runs import true_runs

__all__ = ["CAUSES", "fall_cause", "longest_run"]

#: the causes, in the order their rules are tried
CAUSES = ("crossing", "slip", "estimate", "torque", "reach")
#: s before the fall that the rules read
WINDOW = 0.5
#: s before the fall left out of the slip, estimate and torque rules (the collapse)
LEAD = 0.1
#: horizontal speed of a loaded sole that counts as slipping, m/s; and for how long, s
SLIP_SPEED, SLIP_TIME = 0.3, 0.03
#: estimate errors that count: tilt rad, horizontal base velocity m/s; wrong contact for s
TILT_ERROR, VELOCITY_ERROR, CONTACT_TIME = 0.1, 0.5, 0.06
#: fraction of the torque limit that counts as saturated; and for how long, s
SATURATION, SATURATION_TIME = 0.99, 0.02


def longest_run(mask: np.ndarray) -> int:
    """The longest run of consecutive True rows of ``mask`` (N,) or (N, M) (in any one column), rows."""
    m = np.atleast_2d(np.asarray(mask, dtype=bool).T).T  # (N,) -> (N, 1)
    return max((b - a for col in m.T for a, b in true_runs(col)), default=0)


def _estimate_wrong(a: dict[str, np.ndarray], s: slice, dt: float) -> bool:
    """Rule 3 over the rows ``s`` (module docstring); False when the run has no estimate."""
    if "est_qpos" not in a:
        return False
    tilt = tilt_error(a["est_qpos"][s, 3:7], a["qpos"][s, 3:7])
    vel = np.linalg.norm(a["qvel"][s, :2] - a["est_qvel"][s, :2], axis=1)
    wrong = a["est_contact"][s].astype(bool) != a["contact"][s].astype(bool)
    return bool(np.any(tilt > TILT_ERROR) or np.any(vel > VELOCITY_ERROR) or longest_run(wrong) * dt >= CONTACT_TIME)


def fall_cause(a: dict[str, np.ndarray], fall_time: float, torque_limit: Any, dt: float) -> str:
    """The cause (one of :data:`CAUSES`) of the fall at plan time ``fall_time`` s, from the run's
    arrays ``a`` (:class:`~gaitshift.sim.log.TickLog` keys and the ``est_`` keys when the estimator
    ran), the motors' torque limits ``torque_limit`` (nu,) N m and the tick ``dt`` s."""
    t = a["t"]
    near = (t >= fall_time - WINDOW) & (t <= fall_time)
    if np.any(a["legs_touch"][near]) or np.any(a["feet_overlap"][near]):
        return "crossing"
    s = slice(*np.searchsorted(t, [fall_time - WINDOW, fall_time - LEAD]))
    feet = a["foot_pos"][s, :, :2]
    speed = np.linalg.norm(np.diff(feet, axis=0), axis=2) / dt if len(feet) > 1 else np.zeros((0, 2))
    loaded = a["contact"][s][1:].astype(bool)
    if longest_run((speed > SLIP_SPEED) & loaded) * dt >= SLIP_TIME:
        return "slip"
    if _estimate_wrong(a, s, dt):
        return "estimate"
    limit = np.asarray(torque_limit, dtype=float)
    saturated = np.abs(a["tau"][s]) >= SATURATION * limit
    if longest_run(saturated) * dt >= SATURATION_TIME:
        return "torque"
    return "reach"
