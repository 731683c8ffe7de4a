"""How far the whole-body motion of a plan departs from the plan, and whether it still has the plan's
physics (``IKSettings.check_plan_fit``, the reference IK of ``gaitshift export``).

The IK holds the CoM exactly (3 equations, to ``com_tol``) and every flat sole in contact exactly (to
``pos_tol`` / ``rot_tol``). Two freedoms of the reference IK move a sole off its plan, and each has a
physical condition, checked here on the solved motion q_k (N samples):

* **toe-off** (:func:`gaitshift.wholebody.ik_tasks.trailing_soles`): the rear sole of a double support
  may pivot about its toe edge. Its toe stays where the plan put it; its centre rises by
  ``(L/2) (1 - cos a)`` and its heel by ``L sin a`` for a pivot angle a (L the sole length). A sole
  whose normal is more than ``rot_tol`` from the planned one touches the ground along its toe edge
  only, so the support polygon shrinks to the convex hull H of that edge and the other sole's
  rectangle (the robot's ``sole_size``). The contact forces can only produce the plan's ZMP p_k if
  p_k lies in H: the margin ``min_e n_e . (p_k - a_e)`` over the hull's edges e (a_e a vertex, n_e
  the inward normal; the distance to the nearest edge inside, a lower bound of minus the distance
  outside) must be >= 0. No tolerance beyond 0: outside H the plan's CoM motion needs a tension.
  The IK lets a sole pivot only where the same margin, of the soles where the plan puts them, is >= 0
  (:func:`toe_off_margins`); elsewhere the rear sole stays flat and this check verifies the result.
* **ground**: no corner of a sole in contact (centre +- L/2 along the sole's x, +- W/2 along its y)
  below the ground of the plan's terrain (``meta["terrain"]``) by more than ``pos_tol`` (the IK's own
  position tolerance): a pivoting heel must go up.
* **swing ground**: the same for the soles in the air: a swing sole's soft pitch tips its toe down just
  after lift-off, and a sole whose centre followed the plan's swing path (which starts on the ground)
  would put that toe through the floor. Its centre may rise above the plan's path instead
  (``IKSettings.swing_lift_cost``); the largest rise is reported.

The report (:class:`PlanFit`, in the IK's ``meta["ik"]["plan_fit"]``) also gives the largest CoM and
contact-sole errors and the flight samples solved with soft sole poses (a sole out of reach) with the
largest sole error there, so that an export states how closely its motion is the plan's.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from gaitshift.common.hull import hull_margin
from gaitshift.models.terrain import Terrain


@dataclass(frozen=True)
class PlanFit:
    """Deviation of a solved motion from its plan (module docstring); lengths m, angles rad, times s.

    Attributes:
        com_error_m: max over samples of |c(q_k) - c_k|.
        contact_sole_error_m: max sole-centre error of the soles in contact that do not pivot.
        toe_off_samples: samples where a sole pivots (its normal more than ``rot_tol`` off the plan's).
        toe_off_angle_rad: largest pivot angle; toe_off_rise_m: the largest rise of a pivoting sole's
            centre above its planned place.
        zmp_margin_m: smallest margin of the plan's ZMP inside the support polygon of a pivoting sample
            (None without toe-off); zmp_margin_time_s: when.
        ground_clearance_m: smallest height of a corner of a sole in contact above the ground (negative:
            below; a pivoting heel must rise); ground_clearance_time_s: when.
        swing_clearance_m: the same for the soles in the air (None without swings); swing_clearance_time_s:
            when.
        swing_lift_m: the largest rise of a swing sole's centre above its planned place (0 without
            swings); swing_lift_time_s: when.
        flight_reach_samples: flight samples solved with the soles' poses soft (a sole out of reach,
            ``IKSettings.flight_reach_cost``); flight_reach_error_m: the largest sole-centre error there.
    """

    com_error_m: float
    contact_sole_error_m: float
    toe_off_samples: int
    toe_off_angle_rad: float
    toe_off_rise_m: float
    zmp_margin_m: float | None
    zmp_margin_time_s: float | None
    ground_clearance_m: float
    ground_clearance_time_s: float
    swing_clearance_m: float | None = None
    swing_clearance_time_s: float | None = None
    flight_reach_samples: int = 0
    flight_reach_error_m: float = 0.0
    swing_lift_m: float = 0.0
    swing_lift_time_s: float | None = None

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready fields."""
        return asdict(self)


def sole_frames(model: Any, sites: list[int], qpos: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Sole centres (N, 2, 3) m, sole rotations (N, 2, 3, 3) and whole-body CoM (N, 3) m of each
    configuration of ``qpos`` (N, nq) (MuJoCo forward kinematics)."""
    import mujoco

    d = mujoco.MjData(model)
    n = len(qpos)
    pos, rot, com = np.empty((n, 2, 3)), np.empty((n, 2, 3, 3)), np.empty((n, 3))
    for k in range(n):
        d.qpos[:] = qpos[k]
        mujoco.mj_kinematics(model, d)
        mujoco.mj_comPos(model, d)
        pos[k], rot[k], com[k] = d.site_xpos[sites], d.site_xmat[sites].reshape(2, 3, 3), d.subtree_com[1]
    return pos, rot, com


def _corners(pos: np.ndarray, rot: np.ndarray, size: tuple[float, float]) -> np.ndarray:
    """The four corners (..., 4, 3) of soles at ``pos`` (..., 3) with rotations ``rot`` (..., 3, 3)."""
    half_l, half_w = size[0] / 2, size[1] / 2
    local = np.array([[half_l, half_w, 0], [half_l, -half_w, 0], [-half_l, half_w, 0], [-half_l, -half_w, 0]])
    out: np.ndarray = pos[..., None, :] + np.einsum("...ij,cj->...ci", rot, local)
    return out


def _support_margins(corners: np.ndarray, zmp: np.ndarray, pivot: np.ndarray, down: np.ndarray) -> np.ndarray:
    """Margin (N,) m of ``zmp`` (N, >= 2) inside the support of the soles ``down`` (N, 2) whose corners are
    ``corners`` (N, 2, 4, 3): the toe edge of a sole that pivots (``pivot`` (N, 2)), the whole rectangle
    of the others; +inf where no sole pivots."""
    out = np.full(len(corners), np.inf)
    for k in np.flatnonzero(pivot.any(axis=1)):
        pts = [corners[k, s, :2, :2] if pivot[k, s] else corners[k, s, :, :2] for s in (0, 1) if down[k, s]]
        out[k] = hull_margin(np.concatenate(pts), zmp[k, :2])
    return out


def toe_off_margins(traj: Any, targets: np.ndarray, trailing: np.ndarray, sole_size: tuple[float, float]) -> np.ndarray:
    """Margin (N,) m of the plan's ZMP inside the support a toe-off of the ``trailing`` (N, 2) sole would
    leave: the convex hull of its toe edge and the other sole's rectangle, both where the plan puts them
    (centres ``traj.foot_pos``, rotations ``targets`` (N, 2, 3, 3)); +inf where no sole trails."""
    corners = _corners(np.asarray(traj.foot_pos), targets, sole_size)  # (N, 2, 4, 3)
    return _support_margins(corners, traj.zmp, trailing, np.ones_like(trailing, dtype=bool))


def plan_fit(
    traj: Any,
    model: Any,
    sites: list[int],
    qpos: np.ndarray,
    targets: np.ndarray,
    sole_size: tuple[float, float],
    rot_tol: float,
    reached: np.ndarray | None = None,
) -> PlanFit:
    """The :class:`PlanFit` of the motion ``qpos`` (N, nq) solving the plan ``traj`` (N samples), whose
    sole target rotations were ``targets`` (N, 2, 3, 3), for soles of ``sole_size`` (length, width) m;
    ``reached`` (N,) bool: the flight samples solved with soft sole poses (default none)."""
    pos, rot, com = sole_frames(model, sites, qpos)
    contact = traj.contact.astype(bool)
    normal_dot = np.einsum("nsi,nsi->ns", rot[..., :, 2], targets[..., :, 2])
    angle = np.arccos(np.clip(normal_dot, -1.0, 1.0))
    pivot = contact & (angle > rot_tol)
    sole_err = np.linalg.norm(pos - traj.foot_pos, axis=2)
    flat = contact & ~pivot
    corners = _corners(pos, rot, sole_size)  # (N, 2, 4, 3)
    terrain = Terrain.from_list(traj.meta.get("terrain"))
    clear_each = (corners[..., 2] - terrain.height(corners[..., 0])).min(axis=2)  # (N, 2)
    clear = np.where(contact, clear_each, np.inf).min(axis=1)
    kc = int(np.argmin(clear))
    swing = np.where(contact, np.inf, clear_each).min(axis=1)
    ks = int(np.argmin(swing))
    lift = np.where(contact, -np.inf, pos[..., 2] - traj.foot_pos[..., 2]).max(axis=1)
    kl = int(np.argmax(lift))
    reach = np.zeros(len(qpos), bool) if reached is None else np.asarray(reached, bool)
    margins = _support_margins(corners, traj.zmp, pivot, contact)
    k_margin = int(np.argmin(margins)) if pivot.any() else None
    margin = None if k_margin is None else float(margins[k_margin])
    return PlanFit(
        com_error_m=float(np.linalg.norm(com - traj.com_pos, axis=1).max()),
        contact_sole_error_m=float(sole_err[flat].max()) if flat.any() else 0.0,
        toe_off_samples=int(pivot.any(axis=1).sum()),
        toe_off_angle_rad=float(angle[pivot].max()) if pivot.any() else 0.0,
        toe_off_rise_m=float((pos[..., 2] - traj.foot_pos[..., 2])[pivot].max()) if pivot.any() else 0.0,
        zmp_margin_m=margin,
        zmp_margin_time_s=None if k_margin is None else float(traj.t[k_margin]),
        ground_clearance_m=float(clear[kc]),
        ground_clearance_time_s=float(traj.t[kc]),
        swing_clearance_m=float(swing[ks]) if np.isfinite(swing[ks]) else None,
        swing_clearance_time_s=float(traj.t[ks]) if np.isfinite(swing[ks]) else None,
        flight_reach_samples=int(reach.sum()),
        flight_reach_error_m=float(sole_err[reach].max()) if reach.any() else 0.0,
        swing_lift_m=max(0.0, float(lift[kl])),
        swing_lift_time_s=float(traj.t[kl]) if lift[kl] > 0 else None,
    )


def fit_violation(fit: PlanFit, pos_tol: float) -> tuple[float, str, str] | None:
    """(time s, check, cause) of the first broken condition of ``fit`` (module docstring), or None."""
    if fit.zmp_margin_m is not None and fit.zmp_margin_m < 0 and fit.zmp_margin_time_s is not None:
        cause = (
            f"the plan's ZMP is {-fit.zmp_margin_m * 1e3:.1f} mm outside the support left by the rear sole's "
            "toe-off (its toe edge and the other sole)"
        )
        return fit.zmp_margin_time_s, "toe-off support", cause
    if fit.ground_clearance_m < -pos_tol:
        depth = -fit.ground_clearance_m * 1e3
        cause = f"a sole corner is {depth:.1f} mm below the ground (tolerance {pos_tol * 1e3:g} mm)"
        return fit.ground_clearance_time_s, "ground", cause
    if (
        fit.swing_clearance_m is not None
        and fit.swing_clearance_m < -pos_tol
        and fit.swing_clearance_time_s is not None
    ):
        depth = -fit.swing_clearance_m * 1e3
        cause = f"a swing sole corner is {depth:.1f} mm below the ground (tolerance {pos_tol * 1e3:g} mm)"
        return fit.swing_clearance_time_s, "swing ground", cause
    return None
