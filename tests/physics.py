"""Independent physics checks shared by the planner tests (no gaitshift code used).

Each check takes plain arrays from a trajectory file and returns the worst error it finds.
"""

from __future__ import annotations

import itertools

import numpy as np
from scipy.integrate import solve_ivp
from scipy.spatial import ConvexHull

DS, SS, F = 0, 1, 2


def segments(phase, t=None, boundary_t=None):
    """(start, stop) sample index ranges of constant phase; stop exclusive. With ``boundary_t`` (the
    file's phase boundary times) consecutive phases of the same kind are split too."""
    change = np.flatnonzero(np.diff(phase)) + 1
    if boundary_t is not None:
        extra = np.searchsorted(t, boundary_t[1:-1] - 1e-9)
        change = np.unique(np.r_[change, extra[(extra > 0) & (extra < len(t))]])
    starts = np.r_[0, change]
    stops = np.r_[change, len(phase)]
    return list(zip(starts, stops, strict=True))


def switches(d):
    """Sample indices where a new phase starts (kind changes, or a boundary time of the file)."""
    idx = np.flatnonzero(np.diff(d["phase"])) + 1
    if "boundary_t" in d:
        extra = np.searchsorted(d["t"], d["boundary_t"][1:-1] - 1e-9)
        idx = np.unique(np.r_[idx, extra[(extra > 0) & (extra < len(d["t"]))]])
    return idx


def interior(d, pad=2):
    """Mask of samples at least ``pad`` samples away from any phase switch."""
    phase = d["phase"]
    m = np.ones(len(phase), bool)
    for i in switches(d):
        m[max(0, i - pad) : i + pad] = False
    m[:pad] = m[-pad:] = False
    return m


def eq1_error(d, g):
    """max |p'' - ((p - c)/T^2 - g e_z)| over support samples (eq. (1) of paper 001)."""
    sup = d["phase"] != F
    T = d["stiffness"][sup][:, None]
    pred = (d["com_pos"][sup] - d["zmp"][sup]) / T**2 - np.array([0, 0, g])
    return float(np.max(np.abs(d["com_acc"][sup] - pred)))


def flight_error(d, g):
    """max |p'' + g e_z| over flight samples."""
    fl = d["phase"] == F
    if not fl.any():
        return 0.0
    return float(np.max(np.abs(d["com_acc"][fl] + np.array([0, 0, g]))))


def finite_difference_errors(d):
    """(vel error, acc error) of com_vel, com_acc against central differences of com_pos/com_vel,
    at samples away from phase switches."""
    dt = d["t"][1] - d["t"][0]
    p, v, a = d["com_pos"], d["com_vel"], d["com_acc"]
    m = interior(d)[1:-1]
    vfd = (p[2:] - p[:-2]) / (2 * dt)
    afd = (v[2:] - v[:-2]) / (2 * dt)
    a2 = (p[2:] - 2 * p[1:-1] + p[:-2]) / dt**2
    return (
        float(np.max(np.abs(vfd - v[1:-1])[m])),
        float(np.max(np.abs(afd - a[1:-1])[m])),
        float(np.max(np.abs(a2 - a[1:-1])[m])),
    )


def _segment_rhs(d, a, b, g):
    """Right-hand side of the CoM ODE on segment [a, b): eq. (1) with the sampled T and a ZMP linear
    in time through the segment's first and last samples, or ballistic flight."""
    t = d["t"]
    if d["phase"][a] == F:
        return lambda s, y: np.r_[y[3:], 0.0, 0.0, -g]
    T = d["stiffness"][a]
    c0 = d["zmp"][a]
    slope = (d["zmp"][b - 1] - c0) / (t[b - 1] - t[a])
    return lambda s, y: np.r_[y[3:], (y[:3] - (c0 + slope * (s - t[a]))) / T**2 - np.array([0, 0, g])]


def ode_errors(d, g):
    """Integrate the CoM ODE with solve_ivp, independently of the planner's closed form.

    Returns ``(within, across)``: the worst position error (m) when integrating each phase from its
    first sample over all its samples, and the worst position/velocity error when integrating from
    the last sample of a phase to the boundary time and on with the next phase's dynamics to the
    first sample of that phase (continuity of p and v across every switch).
    """
    t, p, v = d["t"], d["com_pos"], d["com_vel"]
    segs = [(a, b) for a, b in segments(d["phase"], t, d.get("boundary_t")) if b - a >= 3]
    within, across = 0.0, 0.0
    opts = {"rtol": 1e-11, "atol": 1e-12}
    for a, b in segs:
        sol = solve_ivp(_segment_rhs(d, a, b, g), (t[a], t[b - 1]), np.r_[p[a], v[a]], t_eval=t[a:b], **opts)
        within = max(within, float(np.max(np.abs(sol.y[:3].T - p[a:b]))))
    bt = d["boundary_t"]
    for (a, b), (a2, b2) in itertools.pairwise(segs):
        if a2 != b:
            continue
        tb = bt[np.argmin(np.abs(bt - t[a2]))]  # the boundary time between the two phases
        y = np.r_[p[b - 1], v[b - 1]]
        if tb > t[b - 1]:
            y = solve_ivp(_segment_rhs(d, a, b, g), (t[b - 1], tb), y, **opts).y[:, -1]
        if t[a2] > tb:
            y = solve_ivp(_segment_rhs(d, a2, b2, g), (tb, t[a2]), y, **opts).y[:, -1]
        across = max(across, float(np.max(np.abs(y - np.r_[p[a2], v[a2]]))))
    return within, across


def sole_corners(x, y, yaw, size):
    hl, hw = size[0] / 2, size[1] / 2
    loc = np.array([[hl, hw], [-hl, hw], [-hl, -hw], [hl, -hw]])
    c, s = np.cos(yaw), np.sin(yaw)
    return loc @ np.array([[c, s], [-s, c]]) + [x, y]


def zmp_outside_polygon(d, size):
    """Largest distance (m) by which the ZMP lies outside the support polygon: the contacting sole's
    rectangle in SS, the convex hull of both soles in DS. Foot yaw from the nearest footstep."""
    fs = d["footsteps"]
    worst = 0.0
    sup = np.flatnonzero(d["phase"] != F)
    for i in sup[::5]:
        pts = []
        for s in (0, 1):
            if d["contact"][i, s]:
                fp = d["foot_pos"][i, s]
                j = np.argmin(np.linalg.norm(fs[:, :2] - fp[:2], axis=1))
                pts.append(sole_corners(fp[0], fp[1], fs[j, 3], size))
        hull = ConvexHull(np.vstack(pts))
        dist = np.max(hull.equations[:, :2] @ d["zmp"][i, :2] + hull.equations[:, 2])
        worst = max(worst, float(dist))
    return worst
