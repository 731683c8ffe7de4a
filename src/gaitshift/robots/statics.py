"""Statics of a robot in its standing pose: the sole frames, the CoM over the soles, the joint torques.

With the base upright and the lower sole on z = 0, the robot stands still on both soles. Gravity's
generalized force g(q) (nv,) (``mj_rne`` with q̇ = q̈ = 0) is balanced by the two sole wrenches
w = (f_L, m_L, f_R, m_R) (12,) applied at the sole sites and the joint torques τ:

    g_b(q) = J_b(q)ᵀ w                 the 6 rows of the floating base: no actuator there
    τ      = g_j(q) - J_j(q)ᵀ w         the joint rows

(J = [J_pos; J_rot] of each sole site, split in base columns b and joint columns j). Of the wrench
distributions that hold the base, the one with the least Σ (τ_i / τ_max,i)² (plus 1e-9 ||w||² to make
it unique) is the static torque the robot needs at least; it is solved in closed form from the KKT
system of that equality-constrained least-squares problem.

The sole frame is right when each sole's z axis is vertical (within :data:`LEVEL_TOL` rad) and its
x axis points forward (along the base's x axis, within 45°) in the standing pose; a foot link rotated
against the world with ``sole_orientation: body`` fails this.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from gaitshift.robots.config import RobotConfig

#: largest tilt of a sole's normal from the vertical in the standing pose, rad (1°)
LEVEL_TOL = math.radians(1.0)
#: weight of ||w||² that makes the least-torque wrench distribution unique (N⁻², N⁻² m⁻²)
WRENCH_REGULARISATION = 1e-9
#: contact points whose spread (product of their two principal extents, m²) is below this span no area
FLAT_AREA = 1e-8


@dataclass(frozen=True)
class Statics:
    """The standing pose's statics (see module docstring).

    Attributes:
        tilt: (2,) angle of each sole's z axis from the vertical, rad.
        heading: (2,) angle of each sole's x axis from the base's x axis in the ground plane, rad.
        com_margin: signed distance of the CoM's ground projection inside the support polygon, m
            (negative: outside).
        support_area: False when the soles' contact points lie on a line in the ground plane (no support
            polygon: a sole frame on its edge).
        torque: (J,) static joint torques, N m (order of ``RobotConfig.joint_names``).
        torque_fraction: (J,) |τ| / τ_max (0 where the model gives no limit).
        normal_force: (2,) vertical force on each sole, N.
    """

    tilt: np.ndarray
    heading: np.ndarray
    com_margin: float
    support_area: bool
    torque: np.ndarray
    torque_fraction: np.ndarray
    normal_force: np.ndarray


def _support_margin(points: np.ndarray, p: np.ndarray) -> tuple[float, bool]:
    """Signed distance (m) of ``p`` (2,) inside the convex hull of ``points`` (n, 2), and whether that hull
    has an area. Points on a line (or one point: soles seen edge-on, :data:`FLAT_AREA` m²) span no
    polygon: the distance is then minus the distance of ``p`` to their segment (never inside)."""
    from scipy.spatial import ConvexHull

    centred = points - points.mean(axis=0)
    _, sv, vt = np.linalg.svd(centred, full_matrices=False)
    if len(points) < 3 or sv[-1] * sv[0] <= FLAT_AREA:
        axis = vt[0]
        s = np.clip((p - points.mean(axis=0)) @ axis, (centred @ axis).min(), (centred @ axis).max())
        return -float(np.linalg.norm(p - points.mean(axis=0) - s * axis)), False
    hull = ConvexHull(points)
    # hull.equations: n·x + c <= 0 inside, n unit
    return float(-np.max(hull.equations[:, :2] @ p + hull.equations[:, 2])), True


def _standing_data(robot: RobotConfig) -> tuple[Any, Any]:
    import mujoco

    m = robot.model()
    d = mujoco.MjData(m)
    d.qpos[:] = robot.standing_qpos(m)
    mujoco.mj_forward(m, d)
    return m, d


def standing_statics(robot: RobotConfig) -> Statics:
    """The statics of ``robot`` in its standing pose (see module docstring)."""
    import mujoco

    m, d = _standing_data(robot)
    sites = [m.site(s).id for s in robot.SOLE_SITES]
    base_x = d.xmat[int(m.jnt_bodyid[0])].reshape(3, 3)[:, 0]
    tilt, heading, pts = np.zeros(2), np.zeros(2), []
    for i, s in enumerate(sites):
        R = d.site_xmat[s].reshape(3, 3)
        tilt[i] = math.acos(float(np.clip(R[2, 2], -1.0, 1.0)))
        x = R[:2, 0]
        heading[i] = math.atan2(float(base_x[0] * x[1] - base_x[1] * x[0]), float(base_x[:2] @ x))
        pts.append(d.site_xpos[s] + robot.soles[i].points @ R.T)
    margin, area = _support_margin(np.vstack(pts)[:, :2], d.subtree_com[1][:2])
    # gravity's generalized force: qfrc_bias with zero velocity
    g = d.qfrc_bias.copy()
    jp, jr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
    cols = []
    for s in sites:
        mujoco.mj_jacSite(m, d, jp, jr, s)
        cols += [jp.T.copy(), jr.T.copy()]
    Jt = np.hstack(cols)  # (nv, 12): J_solesᵀ
    dofs = np.array([m.jnt_dofadr[m.joint(n).id] for n in robot.joint_names])
    lim = robot.torque_limit
    weight = np.where(np.isfinite(lim) & (lim > 0), 1.0 / np.where(np.isfinite(lim), lim, 1.0), 0.0)
    A, B = weight[:, None] * Jt[dofs], Jt[:6]
    b = weight * g[dofs]
    # min ||b - A w||² + ε||w||²  s.t.  B w = g_b   (KKT)
    H = A.T @ A + WRENCH_REGULARISATION * np.eye(12)
    K = np.block([[H, B.T], [B, np.zeros((6, 6))]])
    w = np.linalg.lstsq(K, np.concatenate([A.T @ b, g[:6]]), rcond=None)[0][:12]
    tau = g[dofs] - Jt[dofs] @ w
    frac = np.where(np.isfinite(lim), np.abs(tau) / np.where(np.isfinite(lim), lim, 1.0), 0.0)
    return Statics(tilt, heading, margin, area, tau, frac, np.array([w[2], w[8]]))
