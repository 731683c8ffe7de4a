"""How well the robot followed the plan's speed and heading (the ``stride_*`` and ``heading_*`` metrics).

* Stride speed: for every window of two consecutive planned steps (single-support start to the
  single-support start two steps later) that the run completed, the **measured** stride-mean
  velocity, i.e. the CoM displacement over the window divided by its duration, in the plan's heading
  frame at the window's middle (the definition of docs/locomotion.md), minus the applied command
  (``command_vel``) of the window. Windows count only where the plan itself is steady: its own
  stride-mean is within 0.03 m/s of the command and the command and the gait do not change in the
  window (ramps, gait switches, starts and stops are excluded: there the command is not the target).
* Heading: the measured pelvis yaw minus the plan's heading (wrapped to [-pi, pi)), over all ticks.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from gaitshift.trajectory.contract import SS, Trajectory

__all__ = ["heading_errors", "stride_speed_errors"]

#: a window is steady when the plan's own stride-mean is this close to the command, m/s
STEADY = 0.03


def _heading_frame(d: np.ndarray, psi: float) -> np.ndarray:
    c, s = math.cos(psi), math.sin(psi)
    return np.array([c * d[0] + s * d[1], -s * d[0] + c * d[1]])


def stride_speed_errors(a: dict[str, np.ndarray], traj: Trajectory) -> dict[str, Any]:
    """Measured stride-mean velocity errors (module docstring): ``stride_speed_errors`` rows of
    [t_start, command vx, command vy, measured vx, measured vy, error norm], with max and RMS."""
    ph = traj.phase
    starts = np.flatnonzero((ph[1:] == SS) & (ph[:-1] != SS)) + 1
    t_end = float(a["t"][-1])
    rows = []
    for i0, i1 in zip(starts[:-2], starts[2:], strict=True):
        t0, t1 = float(traj.t[i0]), float(traj.t[i1])
        cmd = traj.command_vel[i0]
        if t1 > t_end or not np.all(np.isfinite(cmd)):
            continue
        if np.ptp(traj.command_vel[i0:i1], axis=0).max() > 1e-12 or np.ptp(traj.gait[i0:i1]) > 0:
            continue
        psi = 0.5 * (traj.heading[i0] + traj.heading[i1])
        plan_v = _heading_frame(traj.com_pos[i1, :2] - traj.com_pos[i0, :2], psi) / (t1 - t0)
        if np.hypot(*(plan_v - cmd)) > STEADY:
            continue
        m0 = np.array([np.interp(t0, a["t"], a["com_pos"][:, k]) for k in (0, 1)])
        m1 = np.array([np.interp(t1, a["t"], a["com_pos"][:, k]) for k in (0, 1)])
        v = _heading_frame(m1 - m0, psi) / (t1 - t0)
        rows.append([t0, float(cmd[0]), float(cmd[1]), float(v[0]), float(v[1]), float(np.hypot(*(v - cmd)))])
    errs = np.array([r[5] for r in rows])
    return {
        "stride_speed_errors": rows,
        "stride_speed_error_max": float(errs.max()) if len(errs) else math.nan,
        "stride_speed_error_rms": float(np.sqrt(np.mean(errs**2))) if len(errs) else math.nan,
    }


def heading_errors(a: dict[str, np.ndarray], traj: Trajectory) -> dict[str, float]:
    """Measured pelvis yaw minus the plan's heading, rad: max |error| and RMS over the run."""
    qw = a["qpos"][:, 3:7]
    yaw = np.arctan2(2.0 * (qw[:, 0] * qw[:, 3] + qw[:, 1] * qw[:, 2]), 1.0 - 2.0 * (qw[:, 2] ** 2 + qw[:, 3] ** 2))
    err = (yaw - traj.heading[a["plan_index"]] + math.pi) % (2.0 * math.pi) - math.pi
    return {"heading_error_max": float(np.max(np.abs(err))), "heading_error_rms": float(np.sqrt(np.mean(err**2)))}
