"""Figures of paper 001: Figs. 5-8, CoM height and vertical force."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.patches import Polygon

from gaitshift.analysis.physics import capture_point, sole_corners, vertical_force
from gaitshift.models.stiffness import stiffness as solve_stiffness
from gaitshift.models.stiffness import sweep_running
from gaitshift.models.tvlip import flight_state, support_state
from gaitshift.plots.files import save_figure
from gaitshift.trajectory.contract import DS, FLIGHT, SS, Trajectory

PHASE_COLORS = {DS: "#dde8f5", SS: "#ffffff", FLIGHT: "#fbe3d4"}


def _shade_phases(ax: Axes, traj: Trajectory) -> None:
    change = np.flatnonzero(np.diff(traj.phase)) + 1
    starts = np.r_[0, change]
    ends = np.r_[change, len(traj) - 1]
    for a, b in zip(starts, ends, strict=True):
        ax.axvspan(traj.t[a], traj.t[b], color=PHASE_COLORS[int(traj.phase[a])], lw=0, zorder=0)


def top_view(traj: Trajectory, path: Path) -> Path:
    """Fig. 8: footprints, ZMP, CoM and capture points (support only)."""
    fs_xy = traj.footsteps[:, :2]
    span = np.ptp(np.vstack([fs_xy, traj.com_pos[:, :2]]), axis=0) + 0.4
    width = 12.0
    stretched = span[0] > 4 * span[1]
    fig, ax = plt.subplots(
        figsize=(width, 4.5 if stretched else float(np.clip(width * span[1] / span[0], 2.5, 9.0)) + 1.0)
    )
    for fs, side in zip(traj.footsteps, traj.footstep_side, strict=True):
        ax.add_patch(
            Polygon(
                sole_corners(fs, traj.meta["foot_size"]),
                closed=True,
                fill=False,
                ec="tab:blue" if side == 0 else "tab:red",
                lw=1,
            )
        )
    ax.plot(traj.com_pos[:, 0], traj.com_pos[:, 1], "k-", lw=1.2, label="CoM")
    sup = np.isfinite(traj.zmp[:, 0])
    ax.plot(np.where(sup, traj.zmp[:, 0], np.nan), np.where(sup, traj.zmp[:, 1], np.nan), "g-", lw=1.2, label="ZMP")
    _, xi = capture_point(traj)
    ax.plot(xi[:, 0], xi[:, 1], ".", ms=1.5, color="tab:purple", label="capture point (support)")
    if not stretched:
        ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]" + (" (stretched)" if stretched else ""))
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.18), ncol=3, fontsize=8)
    ax.set_title("Top view: footprints (blue left, red right), CoM, ZMP, capture point")
    return save_figure(fig, path)


def capture_point_x(traj: Trajectory, path: Path) -> Path:
    """Capture point, CoM and ZMP along x over time, support phases only for xi and ZMP."""
    fig, ax = plt.subplots(figsize=(10, 3.5))
    _shade_phases(ax, traj)
    mask, xi = capture_point(traj)
    ax.plot(traj.t, traj.com_pos[:, 0], "k-", lw=1, label="CoM x")
    ax.plot(traj.t, traj.zmp[:, 0], "g-", lw=1, label="ZMP x")
    ax.plot(traj.t[mask], xi[:, 0], ".", ms=1, color="tab:purple", label="capture point x")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("x [m]")
    ax.legend(fontsize=8)
    ax.set_title("Capture point during support (shading: blue DS, white SS, orange flight)")
    return save_figure(fig, path)


def height_and_force(traj: Trajectory, path: Path) -> Path:
    """CoM height and vertical force per unit weight (z''+g)/g over time."""
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(10, 5), sharex=True)
    for ax in (a1, a2):
        _shade_phases(ax, traj)
    a1.plot(traj.t, traj.com_pos[:, 2], "k-")
    a1.set_ylabel("CoM z [m]")
    a2.plot(traj.t, vertical_force(traj) / traj.gravity, "tab:red")
    a2.set_ylabel("m(z''+g) / mg")
    a2.set_xlabel("t [s]")
    a1.set_title("CoM height and vertical ground reaction force")
    return save_figure(fig, path)


#: a phase of a vertical CoM figure: (kind, duration s, stiffness T s; None in flight)
VPhase = tuple[int, float, float | None]


def _vertical(z0: float, v0: float, phases: list[VPhase], g: float, n: int = 200) -> tuple[np.ndarray, np.ndarray]:
    """Vertical CoM through ``phases`` [(kind, tau, T)] from (z0, v0) with the ZMP at z = 0."""
    ts, zs = [], []
    t0 = 0.0
    p = np.array([0.0, 0.0, z0])
    v = np.array([0.0, 0.0, v0])
    for kind, tau, T in phases:
        s = np.linspace(0, tau, n)
        if kind == FLIGHT:
            P, V, _ = flight_state(p, v, s, g)
        else:
            zero = np.zeros(3)
            P, V, _, _ = support_state(p, v, zero, zero, np.full(n, T), np.full(n, tau), s, g)
        ts.append(t0 + s)
        zs.append(P[:, 2])
        p, v, t0 = P[-1], V[-1], t0 + tau
    return np.concatenate(ts), np.concatenate(zs)


def _vertical_figure(
    h: float, v0: float, phases: list[VPhase], g: float, title: str, path: Path, size: tuple[float, float]
) -> Path:
    """Plot the vertical CoM through ``phases`` [(kind, tau, T)] from (h, v0), phases shaded."""
    t, z = _vertical(h, v0, phases, g)
    fig, ax = plt.subplots(figsize=size)
    edges = np.cumsum([0.0] + [tau for _, tau, _ in phases])
    for a, b, (kind, _, _) in zip(edges[:-1], edges[1:], phases, strict=True):
        ax.axvspan(a, b, color=PHASE_COLORS[kind], lw=0)
    ax.plot(t, z, "k-")
    ax.axhline(h, ls=":", c="gray")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("CoM z [m]")
    ax.set_title(title)
    return save_figure(fig, path)


def paper_figures_vertical(h: float, tss: float, tds: float, tf: float, g: float, out: Path) -> list[Path]:
    """Figs. 5 (running half cycle), 6 (walk-to-run transition) and 7 (T_r surface)."""
    k = solve_stiffness(h, tss, tds, tf, g)
    paths = [
        _vertical_figure(
            h,
            k.v_r,
            [(SS, tss, k.T_r), (FLIGHT, tf, None)],
            g,
            f"Fig. 5: running half cycle, T_r = {k.T_r:.4f} s, v_r = {k.v_r:.4f} m/s",
            out / "fig5_running_half_cycle.png",
            (6, 3.5),
        ),
        _vertical_figure(
            h,
            0.0,
            [
                (DS, tds, k.T_w),
                (DS, tds, k.T_t0),
                (SS, tss, k.T_t1),
                (FLIGHT, tf, None),
                (SS, tss, k.T_r),
                (FLIGHT, tf, None),
            ],
            g,
            f"Fig. 6: walk->run, T_w={k.T_w:.3f}, T_t0={k.T_t0:.3f}, T_t1={k.T_t1:.3f}, T_r={k.T_r:.3f}",
            out / "fig6_transition.png",
            (7, 3.5),
        ),
    ]
    grid = np.round(np.arange(0.10, 0.395, 0.01), 2)
    S, F = np.meshgrid(grid, grid, indexing="ij")
    Tr, _, _, _ = sweep_running(h, S, F, g)
    fig = plt.figure(figsize=(6, 5))
    ax3 = fig.add_subplot(projection="3d")
    ax3.plot_surface(S, F, Tr, cmap="viridis")
    ax3.set_xlabel("tau_SS [s]")
    ax3.set_ylabel("tau_F [s]")
    ax3.set_zlabel("T_r [s]")
    ax3.set_title(f"Fig. 7: T_r over 900 timings, h = {h} m")
    paths.append(save_figure(fig, out / "fig7_Tr_surface.png"))
    return paths


def write_figures(traj: Trajectory, out: Path) -> list[Path]:
    """Every TV-LIPM figure for a planned trajectory into folder ``out``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    paths = [
        top_view(traj, out / "top_view.png"),
        capture_point_x(traj, out / "capture_point.png"),
        height_and_force(traj, out / "com_height_force.png"),
    ]
    sc = traj.meta["scenario"]["timing"]
    paths += paper_figures_vertical(
        traj.meta["height"], sc["single_support"], sc["double_support"], sc["flight"], traj.gravity, out
    )
    return paths
