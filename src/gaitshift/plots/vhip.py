"""Figures of paper 003 (online VHIP running): Figs. 3, 4 and 7 from a trajectory file.

* Fig. 3 ``fig3_start.png``: lateral (and forward) ZMP and CoM during State Switching 1, with the
  knot of the two cubic ZMP segments and the support polygon bounds.
* Fig. 4 ``fig4_run.png``: the complete run: footholds, ZMP and CoM in x and y over time, with the
  start / cyclic running / stop shaded, and commanded vs planned forward and lateral speed.
* Fig. 7 ``fig7_speed.png``: commanded vs planned forward speed, take-offs circled.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from gaitshift.plots.files import save_figure
from gaitshift.trajectory.contract import DS, FLIGHT, SS, Trajectory

__all__ = ["fig3_start", "fig4_run", "fig7_speed", "write_figures"]


def _takeoffs(traj: Trajectory) -> np.ndarray:
    """Indices of take-off samples: the first force-free sample after a single support."""
    ph = traj.phase
    return np.flatnonzero((ph[1:] == FLIGHT) & (ph[:-1] == SS)) + 1


def _segments(traj: Trajectory) -> tuple[int, int]:
    """End of the start double support, start of the final double support (sample indices)."""
    ds = np.flatnonzero(traj.phase == DS)
    first_end = int(ds[np.flatnonzero(np.diff(ds) > 1)[0]]) if np.any(np.diff(ds) > 1) else int(ds[-1])
    last_start = int(ds[np.flatnonzero(np.diff(ds) > 1)[-1] + 1]) if np.any(np.diff(ds) > 1) else len(traj) - 1
    return first_end, last_start


def fig3_start(traj: Trajectory, path: Path) -> Path:
    """Fig. 3: ZMP and CoM in y (top) and x (bottom) during the start, knot marked."""
    first_end, _ = _segments(traj)
    tk = _takeoffs(traj)
    stop = int(tk[0]) + 1 if len(tk) else first_end + 1
    sl = slice(0, stop)
    t = traj.t[sl]
    half = np.asarray(traj.meta["foot_size"], float) / 2
    fig, axes = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    for ax, k, name in ((axes[0], 1, "y"), (axes[1], 0, "x")):
        ax.axvspan(0, traj.t[first_end], color="#e6e6e6", lw=0, label="double support")
        ax.plot(t, traj.zmp[sl, k], "r-", label=f"ZMP {name}")
        ax.plot(t, traj.com_pos[sl, k], "b-", label=f"CoM {name}")
        feet = traj.foot_pos[0, :, k]
        lo, hi = feet.min() - half[1 - k], feet.max() + half[1 - k]
        ax.axhline(lo, color="k", ls=":", lw=0.8)
        ax.axhline(hi, color="k", ls=":", lw=0.8, label="support polygon")
        # knot: the largest change of ZMP curvature in double support (second differences)
        z = traj.zmp[: first_end + 1, k]
        if len(z) > 4:
            jump = np.abs(np.diff(z, 3))
            j = int(np.argmax(jump)) + 2
            if jump[j - 2] > 1e-12:
                ax.plot(traj.t[j], z[j], "ko", ms=5, label="knot (y_m)")
                slope = (z[j + 1] - z[j - 1]) / (traj.t[j + 1] - traj.t[j - 1])
                dtl = 0.15
                ax.plot([traj.t[j] - dtl, traj.t[j] + dtl], [z[j] - slope * dtl, z[j] + slope * dtl], "k-", lw=1)
        ax.set_ylabel(f"{name} [m]")
        ax.legend(loc="best", fontsize=7)
    axes[1].set_xlabel("t [s]")
    axes[0].set_title("State Switching 1: segmented cubic ZMP and CoM (paper 003, Fig. 3)")
    return save_figure(fig, path)


def fig4_run(traj: Trajectory, path: Path) -> Path:
    """Fig. 4: footholds, ZMP, CoM over time (x, y) and commanded vs planned speed."""
    first_end, last_start = _segments(traj)
    tk = _takeoffs(traj)
    fig, axes = plt.subplots(3, 1, figsize=(9, 9), sharex=True)
    for ax in axes:
        ax.axvspan(0, traj.t[first_end], color="#f4c7c3", lw=0)
        ax.axvspan(traj.t[first_end], traj.t[last_start], color="#d9ead3", lw=0)
        ax.axvspan(traj.t[last_start], traj.t[-1], color="#cfe2f3", lw=0)
    sup = traj.phase != FLIGHT
    for ax, k, name in ((axes[0], 0, "x"), (axes[1], 1, "y")):
        ax.plot(traj.t, traj.com_pos[:, k], "b-", lw=1, label=f"CoM {name}")
        ax.plot(traj.t[sup], traj.zmp[sup, k], "r.", ms=1, label=f"ZMP {name}")
        for s, color in ((0, "g"), (1, "m")):
            on = traj.contact[:, s]
            ax.plot(
                traj.t[on],
                traj.foot_pos[on, s, k],
                ".",
                color=color,
                ms=1,
                label=("left" if s == 0 else "right") + " foothold",
            )
        ax.set_ylabel(f"{name} [m]")
        ax.legend(loc="best", fontsize=7, markerscale=6)
    ax = axes[2]
    ax.plot(traj.t, traj.command_vel[:, 0], "k--", label="commanded vx")
    ax.plot(traj.t, traj.com_vel[:, 0], "b-", lw=1, label="planned vx")
    ax.plot(traj.t, traj.command_vel[:, 1], "--", color="gray", label="commanded vy")
    ax.plot(traj.t, traj.com_vel[:, 1], "c-", lw=0.8, label="planned vy")
    ax.plot(traj.t[tk], traj.com_vel[tk, 0], "o", mfc="none", mec="k", ms=5, label="take-off")
    ax.set_ylabel("speed [m/s]")
    ax.set_xlabel("t [s]")
    ax.legend(loc="best", fontsize=7)
    axes[0].set_title("Complete run: start (red), cyclic running (green), stop (blue) (paper 003, Fig. 4)")
    return save_figure(fig, path)


def fig7_speed(traj: Trajectory, path: Path) -> Path:
    """Fig. 7: commanded and planned forward speed; the planned take-off speeds circled."""
    tk = _takeoffs(traj)
    fig, ax = plt.subplots(figsize=(9, 3.5))
    ax.step(traj.t, traj.command_vel[:, 0], "k--", where="post", label="commanded")
    ax.plot(traj.t, traj.com_vel[:, 0], "b-", lw=1, label="planned")
    ax.plot(traj.t[tk], traj.com_vel[tk, 0], "o", mfc="none", mec="r", ms=7, label="planned at take-off")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("forward speed [m/s]")
    ax.set_title("Speed tracking: the take-off speed reaches the command two steps later (paper 003, Fig. 7)")
    ax.legend(loc="best", fontsize=8)
    return save_figure(fig, path)


def write_figures(traj: Trajectory, out_dir: str | Path) -> list[Path]:
    """Write Figs. 3, 4 and 7 of paper 003 for a ``vhip`` trajectory into ``out_dir``."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    return [
        fig3_start(traj, out / "fig3_start.png"),
        fig4_run(traj, out / "fig4_run.png"),
        fig7_speed(traj, out / "fig7_speed.png"),
    ]
