"""Figures of a locomotion plan (docs/locomotion.md).

* ``speed.png``: the stride-mean speed (CoM displacement over two steps, heading frame) against the
  applied command, with the planned CoM speed, the yaw rate and the heading; standing, walking,
  running and the walk/run transition steps shaded.
* ``top.png``: footsteps (rotated soles, left/right colours), the CoM and ZMP paths, seen from above.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import itertools

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Polygon

from gaitshift.plots.files import save_figure
from gaitshift.trajectory.contract import SS, Trajectory

__all__ = ["speed_figure", "top_figure", "write_figures"]

SHADE = {0: ("stand", "#dddddd"), 1: ("walk", "#cfe8cf"), 2: ("run", "#f6d5c3")}
#: step_type codes of the transition steps (gaitshift.planners.locomotion.steps.STEP_CODES)
TRANSITIONS = (3, 4, 6)


def _ss_starts(traj: Trajectory) -> np.ndarray:
    ph = traj.phase
    return np.flatnonzero((ph[1:] == SS) & (ph[:-1] != SS)) + 1


def _shade(ax: Any, traj: Trajectory) -> None:
    gait = traj.gait
    change = np.flatnonzero(np.diff(gait)) + 1
    edges = np.r_[0, change, len(gait) - 1]
    used = set()
    for a, b in itertools.pairwise(edges):
        name, colour = SHADE[int(gait[a])]
        ax.axvspan(traj.t[a], traj.t[b], color=colour, lw=0, label=None if name in used else name)
        used.add(name)
    # the walk/run transition steps (walk_to_run, run_start, run_to_walk)
    kind = traj.extras["step_type"]
    trans = np.isin(kind, list(TRANSITIONS))
    edges = np.flatnonzero(np.diff(np.r_[0, trans.astype(np.int8), 0]))
    for k, (a, b) in enumerate(zip(edges[::2], edges[1::2], strict=True)):
        ax.axvspan(
            traj.t[a],
            traj.t[min(b, len(trans) - 1)],
            color="#b05090",
            alpha=0.35,
            lw=0,
            label="walk/run transition" if k == 0 and "transition" not in used else None,
        )
        used.add("transition")


def speed_figure(traj: Trajectory, path: Path) -> Path:
    """Stride-mean speed vs command, yaw rate and heading over time (module docstring)."""
    s = _ss_starts(traj)
    hd = traj.heading
    tm, vs = [], []
    for a, b in zip(s[:-2], s[2:], strict=True):
        d = traj.com_pos[b, :2] - traj.com_pos[a, :2]
        psi = 0.5 * (hd[a] + hd[b])
        vs.append([np.cos(psi) * d[0] + np.sin(psi) * d[1], -np.sin(psi) * d[0] + np.cos(psi) * d[1]])
        vs[-1] = [x / (traj.t[b] - traj.t[a]) for x in vs[-1]]
        tm.append(0.5 * (traj.t[a] + traj.t[b]))
    vs_a = np.array(vs).reshape(-1, 2)
    fig, axes = plt.subplots(3, 1, figsize=(10, 8), sharex=True)
    ax = axes[0]
    _shade(ax, traj)
    ax.plot(traj.t, traj.command_vel[:, 0], "k-", lw=1.2, label="command vx")
    c, sn = np.cos(hd), np.sin(hd)
    v_head = c * traj.com_vel[:, 0] + sn * traj.com_vel[:, 1]
    ax.plot(traj.t, v_head, color="#5577aa", lw=0.6, alpha=0.7, label="CoM speed (heading frame)")
    ax.plot(tm, vs_a[:, 0], "o", ms=3.5, color="#c03020", label="stride-mean vx")
    ax.set_ylabel("forward speed (m/s)")
    ax.legend(loc="upper left", fontsize=8, ncol=3)
    ax = axes[1]
    _shade(ax, traj)
    ax.plot(traj.t, traj.command_vel[:, 1], "k-", lw=1.2, label="command vy")
    ax.plot(tm, vs_a[:, 1], "o", ms=3.5, color="#c03020", label="stride-mean vy")
    ax.set_ylabel("lateral speed (m/s)")
    ax.legend(loc="upper left", fontsize=8)
    ax = axes[2]
    _shade(ax, traj)
    ax.plot(traj.t, traj.command_yaw_rate, "k-", lw=1.2, label="command yaw rate (rad/s)")
    ax.plot(traj.t, np.gradient(hd, traj.t), color="#c03020", lw=1.0, label="planned yaw rate (rad/s)")
    ax.plot(traj.t, hd, color="#5577aa", lw=1.0, label="heading (rad)")
    ax.set_xlabel("t (s)")
    ax.legend(loc="upper left", fontsize=8)
    fig.suptitle(
        f"{traj.meta.get('scenario', '')}: speed, command and gait "
        "(shaded: standing / walking / running / transition steps)"
    )
    return save_figure(fig, path)


def top_figure(traj: Trajectory, path: Path) -> Path:
    """Footsteps, CoM and ZMP seen from above (module docstring)."""
    L, W = traj.meta["foot_size"]
    fig, ax = plt.subplots(figsize=(9, 9))
    corners = np.array([[L, W], [-L, W], [-L, -W], [L, -W]]) / 2
    for (x, y, _, yaw), side in zip(traj.footsteps, traj.footstep_side, strict=True):
        R = np.array([[np.cos(yaw), -np.sin(yaw)], [np.sin(yaw), np.cos(yaw)]])
        ax.add_patch(
            Polygon(corners @ R.T + [x, y], closed=True, fill=False, ec="#2060c0" if side == 0 else "#c04020", lw=0.9)
        )
    ax.plot(traj.com_pos[:, 0], traj.com_pos[:, 1], "k-", lw=1.0, label="CoM")
    ax.plot(traj.zmp[:, 0], traj.zmp[:, 1], color="#30a030", lw=0.6, label="ZMP")
    ax.plot([], [], color="#2060c0", label="left soles")
    ax.plot([], [], color="#c04020", label="right soles")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.legend(loc="best", fontsize=8)
    ax.set_title(f"{traj.meta.get('scenario', '')}: footsteps and CoM path")
    return save_figure(fig, path)


def write_figures(traj: Trajectory, out_dir: str | Path) -> list[Path]:
    """Write ``speed.png`` and ``top.png`` into ``out_dir``."""
    out = Path(out_dir)
    return [speed_figure(traj, out / "speed.png"), top_figure(traj, out / "top.png")]
