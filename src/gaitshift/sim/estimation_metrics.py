"""How well the state estimator tracked the truth over a run: the ``"estimation"`` object of the metrics.

From the run's arrays (truth: ``qpos``, ``qvel``, ``contact`` (contact list), ``com_pos``, ``com_vel``;
estimate: ``est_*`` of :class:`gaitshift.sim.log.EstimationLog`), over the ticks after the first
(tick 0 is the known start state):

* ``base_vel_rmse``: ``sqrt(mean |v_hat - v|^2)`` of the base origin's 3D velocity, m/s;
* ``tilt_rmse``: RMS of the tilt error, rad: the angle between the vertical as the estimated and the
  true base frames see it (:func:`gaitshift.common.rotations.tilt_error`; a heading error alone is none);
* ``yaw_drift``: ``|yaw_hat - yaw|`` of the base at the last tick (wrapped to [0, pi]), rad;
* ``pos_drift_per_m``: horizontal base position error at the last tick over the horizontal distance the
  base travelled (sum of ``|dp_xy|``), m/m (null below 0.1 m travelled);
* ``contact_accuracy``: fraction of ticks where both estimated stance flags equal the truth: the sole
  carries a nonzero normal force (a sole sphere in MuJoCo's contact list whose contact force has a
  positive normal component; a listed contact with zero force, e.g. a sphere inside the contact margin
  after lift-off, is no contact); ``contact_accuracy_list``: the same against the contact list alone;
  ``contact_accuracy_force``: the same for the force-confirmed ``est_stance`` (the scheduler's flags);
* ``com_rmse``, ``com_vel_rmse``: 3D CoM position (m) and velocity (m/s) RMS errors;
* ``slip_ticks``: ticks with a slip flag; ``tick_us``: median cost of ``StateEstimator.step``, µs;
* ``used_by_controller``: true for ``state="estimated"`` (in oracle runs the estimator runs alongside).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from gaitshift.common.rotations import roll_pitch_yaw, tilt_error


def _rms(err: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.sum(err**2, axis=-1)))) if len(err) else math.nan


def estimation_errors(a: dict[str, np.ndarray]) -> dict[str, Any]:
    """The ``"estimation"`` object (module docstring) of the run arrays ``a``."""
    n = len(a["t"])
    if n < 2 or "est_qpos" not in a:
        return {}
    s = slice(1, n)
    q, qh = a["qpos"][s], a["est_qpos"][s]
    tilt = tilt_error(qh[:, 3:7], q[:, 3:7])
    dyaw = roll_pitch_yaw(qh[-1, 3:7])[2] - roll_pitch_yaw(q[-1, 3:7])[2]
    travelled = float(np.sum(np.linalg.norm(np.diff(a["qpos"][:, :2], axis=0), axis=1)))
    drift = float(np.linalg.norm(qh[-1, :2] - q[-1, :2]))
    cost = a["est_tick_us"][s]
    loaded = a["contact"][s] & (a["grf"][s, :, 2] > 0.0)
    return {
        "base_vel_rmse": _rms(a["est_qvel"][s, :3] - a["qvel"][s, :3]),
        "tilt_rmse": float(np.sqrt(np.mean(tilt**2))),
        "yaw_drift": float(abs(math.remainder(float(dyaw), 2 * math.pi))),
        "pos_drift_per_m": drift / travelled if travelled >= 0.1 else None,
        "pos_drift": drift,
        "distance": travelled,
        "contact_accuracy": float(np.mean(np.all(a["est_contact"][s] == loaded, axis=1))),
        "contact_accuracy_list": float(np.mean(np.all(a["est_contact"][s] == a["contact"][s], axis=1))),
        "contact_accuracy_force": float(np.mean(np.all(a["est_stance"][s] == loaded, axis=1)))
        if "est_stance" in a
        else None,
        "com_rmse": _rms(a["est_com"][s] - a["com_pos"][s]),
        "com_vel_rmse": _rms(a["est_com_vel"][s] - a["com_vel"][s]),
        "slip_ticks": int(np.sum(np.any(a["est_slip"][s], axis=1))),
        "tick_us": float(np.median(cost)),
        "friction_assumed_final": float(a["est_mu"][-1]),
    }


def sensing_metrics(a: dict[str, np.ndarray], state: str) -> dict[str, Any]:
    """``{"state_source": state, "estimation": {...}}`` for the metrics of a run."""
    est = estimation_errors(a)
    if est:
        est["used_by_controller"] = state == "estimated"
    return {"state_source": state, "estimation": est}
