"""Analyses of a planned trajectory: capture point, support-polygon margins, vertical force.

Capture point (paper 001 §IV-B, Fig. 8): for the TV-LIPM with stiffness T the instantaneous capture
point is xi = p + T v (horizontal components), defined during support only.
"""

from __future__ import annotations

import numpy as np

from .trajectory import FLIGHT, Trajectory


def capture_point(traj: Trajectory) -> tuple[np.ndarray, np.ndarray]:
    """Capture point xi = p_xy + T v_xy during support.

    Returns ``(mask, xi)``: mask (N,) True in support; xi (K, 2) for the masked samples, m.
    """
    mask = traj.phase != FLIGHT
    T = traj.stiffness[mask][:, None]
    return mask, traj.com_pos[mask, :2] + T * traj.com_vel[mask, :2]


def vertical_force(traj: Trajectory, mass: float = 1.0) -> np.ndarray:
    """Vertical ground reaction force m (z'' + g), N, shape (N,). With mass=1 it is per kg."""
    return mass * (traj.com_acc[:, 2] + traj.gravity)


def sole_corners(footstep: np.ndarray, foot_size) -> np.ndarray:
    """Corners (4, 2) of the sole rectangle of a foothold (x, y, z, yaw) with size [length, width]."""
    x, y, _, yaw = footstep
    hl, hw = foot_size[0] / 2, foot_size[1] / 2
    local = np.array([[hl, hw], [-hl, hw], [-hl, -hw], [hl, -hw]])
    c, s = np.cos(yaw), np.sin(yaw)
    return local @ np.array([[c, s], [-s, c]]) + np.array([x, y])


def zmp_support_margin(traj: Trajectory) -> np.ndarray:
    """Signed distance of the ZMP inside the support polygon, m, shape (K,) over support samples
    (positive inside). The polygon is the contacting sole (SS) or the convex hull of both (DS)."""
    from scipy.spatial import ConvexHull

    foot_size = traj.meta["foot_size"]
    mask = traj.phase != FLIGHT
    out = np.empty(int(mask.sum()))
    zmp = traj.zmp[mask, :2]
    feet = traj.foot_pos[mask]
    contact = traj.contact[mask]
    yaw_of = _foot_yaw(traj)[mask]
    for i in range(len(zmp)):  # analysis only, not a hot path
        pts = np.vstack([sole_corners(np.r_[feet[i, s], yaw_of[i, s]], foot_size)
                         for s in (0, 1) if contact[i, s]])
        hull = ConvexHull(pts)
        eq = hull.equations  # a.x + b <= 0 inside
        out[i] = -np.max(eq[:, :2] @ zmp[i] + eq[:, 2])
    return out


def _foot_yaw(traj: Trajectory) -> np.ndarray:
    """Yaw (N, 2) of each foot: the yaw of the footstep it stands on (nearest foothold)."""
    fs = traj.footsteps
    yaw = np.zeros((len(traj), 2))
    for s in (0, 1):
        d = np.linalg.norm(traj.foot_pos[:, s, None, :2] - fs[None, :, :2], axis=2)
        yaw[:, s] = fs[np.argmin(d, axis=1), 3]
    return yaw
