"""Analyses of a planned trajectory: capture point, support-polygon margins, vertical force.

Capture point (paper 001 §IV-B, Fig. 8): for the TV-LIPM with stiffness T the instantaneous capture
point is xi = p + T v (horizontal components), defined during support only.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from gaitshift.common.hull import hull_margins
from gaitshift.trajectory.contract import FLIGHT, Trajectory


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


def sole_corners(footstep: np.ndarray, foot_size: Sequence[float]) -> np.ndarray:
    """Corners (4, 2) of the sole rectangle of a foothold (x, y, z, yaw) with size [length, width]."""
    x, y, _, yaw = footstep
    hl, hw = foot_size[0] / 2, foot_size[1] / 2
    local = np.array([[hl, hw], [-hl, hw], [-hl, -hw], [hl, -hw]])
    c, s = np.cos(yaw), np.sin(yaw)
    return np.asarray(local @ np.array([[c, s], [-s, c]]) + np.array([x, y]))


def zmp_support_margin(traj: Trajectory) -> np.ndarray:
    """Signed distance of the ZMP inside the support polygon, m, shape (K,) over support samples
    (positive inside). The polygon is the contacting sole (SS) or the convex hull of both (DS), each
    sole rotated by its yaw (``foot_yaw``)."""
    foot_size = traj.meta["foot_size"]
    mask = traj.phase != FLIGHT
    out = np.empty(int(mask.sum()))
    zmp = traj.zmp[mask, :2]
    feet = traj.foot_pos[mask]
    contact = traj.contact[mask]
    yaw = traj.foot_yaw[mask]
    pose = np.concatenate([feet, yaw[:, :, None]], axis=2)  # (K, 2, 4) x, y, z, yaw
    # one hull per distinct (contact, feet) configuration: feet do not move while in contact
    key = np.round(np.where(contact[:, :, None], pose, np.nan), 9).reshape(len(zmp), -1)
    _, inverse = np.unique(np.nan_to_num(key, nan=1e9), axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    for u in np.unique(inverse):
        rows = np.flatnonzero(inverse == u)
        i = rows[0]
        soles = [pose[i, s] for s in (0, 1) if contact[i, s]]
        out[rows] = hull_margins(np.vstack([sole_corners(f, foot_size) for f in soles]), zmp[rows])
    return out


def physics_report(traj: Trajectory) -> dict[str, float]:
    """Worst-case physics errors of a trajectory file, planner-independent.

    * ``zmp_identity``: max |zmp_xy - (p_xy - (p_z - zmp_z)/(p''_z + g) p''_xy)| in support where the
      ground pushes (p''_z + g > 0; elsewhere ``min_vertical_force`` fails), m. This is eq. (2) of
      paper 003 and, with T^2 = (p_z - c_z)/(p''_z + g), the horizontal part of eq. (1) of 001.
    * ``flight_acc``: max |p'' + g e_z| in flight, m/s^2.
    * ``min_vertical_force``: min (p''_z + g) in support, m/s^2 (must be > 0: no pulling ground).
    * ``fd_velocity``, ``fd_acceleration``: max mismatch of com_vel/com_acc against central differences
      of com_pos/com_vel away from phase switches, m/s and m/s^2.
    * ``position_jump``: max |p_i+1 - p_i - dt (v_i + v_i+1)/2| over all samples, m (continuity).
    * ``zmp_outside``: max distance of the ZMP outside the support polygon, m (<= 0 inside).
    * ``start_speed``, ``end_speed``: |v| at the first and last sample, m/s.

    Every value is finite (the contract bounds all inputs to 1e6 and g to >= 1e-3, so even p''_z + g
    of one ulp keeps the predicted ZMP below 1e31), except ``min_vertical_force`` = inf when no
    sample is in support.
    """
    g = traj.gravity
    p, v, a = traj.com_pos, traj.com_vel, traj.com_acc
    sup = traj.phase != FLIGHT
    force = a[sup, 2] + g
    push = np.flatnonzero(sup)[force > 0]
    pred = p[push, :2] - ((p[push, 2] - traj.zmp[push, 2]) / (a[push, 2] + g))[:, None] * a[push, :2]
    identity = np.abs(traj.zmp[push, :2] - pred)
    rep: dict[str, float] = {
        "zmp_identity": float(np.max(identity)) if len(push) else 0.0,
        "flight_acc": float(np.max(np.abs(a[~sup] + [0, 0, g]))) if (~sup).any() else 0.0,
        "min_vertical_force": float(np.min(force)) if sup.any() else float("inf"),
    }
    dt = traj.dt
    switch = np.zeros(len(traj), bool)
    edges = np.flatnonzero(np.diff(traj.phase) != 0) + 1
    # a step of a piecewise-constant stiffness T inside a support phase (the TV-LIPM's transition
    # phases) is a boundary too: a = (p - c)/T^2 - g jumps there. Files without ``boundary_t`` (CSV)
    # keep that knowledge this way; a T that varies from sample to sample (VHIP) has no isolated step.
    change = np.diff(np.nan_to_num(traj.stiffness, nan=-1.0)) != 0
    step = change & ~np.r_[False, change[:-1]] & ~np.r_[change[1:], False]
    edges = np.r_[edges, np.flatnonzero(step) + 1]
    bt = traj.extras.get("boundary_t")
    if bt is not None:
        edges = np.r_[edges, np.searchsorted(traj.t, np.asarray(bt) - 1e-9)]
    for off in (-2, -1, 0, 1):
        switch[np.clip(edges + off, 0, len(traj) - 1)] = True
    inner = ~(switch[:-2] | switch[1:-1] | switch[2:])
    vfd = (p[2:] - p[:-2]) / (2 * dt)
    afd = (v[2:] - v[:-2]) / (2 * dt)
    rep["fd_velocity"] = float(np.max(np.abs(vfd - v[1:-1])[inner])) if inner.any() else 0.0
    rep["fd_acceleration"] = float(np.max(np.abs(afd - a[1:-1])[inner])) if inner.any() else 0.0
    rep["position_jump"] = float(np.max(np.abs(p[1:] - p[:-1] - dt * (v[1:] + v[:-1]) / 2)))
    rep["zmp_outside"] = float(-np.min(zmp_support_margin(traj))) if sup.any() else 0.0
    rep["start_speed"] = float(np.linalg.norm(v[0]))
    rep["end_speed"] = float(np.linalg.norm(v[-1]))
    return rep


#: Pass thresholds of ``gaitshift check`` at dt = 1 ms (same units as :func:`physics_report`).
CHECK_LIMITS = {
    "zmp_identity": 1e-6,
    "flight_acc": 1e-9,
    "fd_velocity": 1e-3,
    "fd_acceleration": 1e-2,
    "position_jump": 1e-5,
    "zmp_outside": 1e-3,
    "start_speed": 1e-3,
    "end_speed": 1e-3,
}


def check_limits(dt: float) -> dict[str, float]:
    """:data:`CHECK_LIMITS` for sampling step ``dt``: the truncation error of a central difference grows
    as dt^2 (velocity, acceleration) and of the trapezoid continuity test as dt^3, so those limits
    scale with (dt / 1 ms)^2 and (dt / 1 ms)^3; the physical identities keep their limits."""
    r = max(dt / 1e-3, 1.0)
    lim = dict(CHECK_LIMITS)
    lim["fd_velocity"] *= r**2
    lim["fd_acceleration"] *= r**2
    lim["position_jump"] *= r**3
    return lim
