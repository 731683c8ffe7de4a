"""Fig. 9 of paper 001: CoM of the 3D-SLIP and the time-varying LIPM over one periodic half cycle."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.figure import Figure

from gaitshift.analysis.slip_compare import SlipComparison
from gaitshift.plots.files import save_figure


def figure(cmp: SlipComparison) -> Figure:
    """A 3 x 2 figure: x, y, z of both models against time (left) and their difference (right).

    The stance phase is shaded. Returns the matplotlib Figure.
    """
    hc = cmp.gait.half_cycle
    fig, axes = plt.subplots(3, 2, figsize=(10, 7.5), sharex=True, gridspec_kw={"width_ratios": [1.6, 1.0]})
    labels = ("x", "y", "z")
    diff = (cmp.tvlip_pos - cmp.slip_pos) * 1e3
    for i, name in enumerate(labels):
        ax, axd = axes[i]
        for a in (ax, axd):
            a.axvspan(hc.t_touchdown, hc.t_liftoff, color="0.9", lw=0)
            a.grid(True, lw=0.3)
        ax.plot(cmp.t, cmp.slip_pos[:, i], color="C0", lw=2.2, label="3D-SLIP")
        ax.plot(cmp.t, cmp.tvlip_pos[:, i], color="C3", lw=1.2, ls="--", label="TV-LIPM (eqs. 3-6)")
        if i == 0:
            ax.plot(
                [hc.t_touchdown, hc.t_liftoff],
                [hc.foot[0]] * 2,
                color="k",
                lw=0.8,
                marker="|",
                ms=8,
                label=f"foot = ZMP (y = {hc.foot[1]:.3f} m)",
            )
        ax.set_ylabel(f"{name} [m]")
        axd.plot(cmp.t, diff[:, i], color="C2")
        axd.set_ylabel(f"TV-LIPM - SLIP, {name} [mm]")
        axd.set_title(f"max |d{name}| = {cmp.max_deviation[i] * 1e3:.1f} mm", fontsize=9)
    axes[0, 0].legend(loc="upper left", fontsize=8)
    axes[-1, 0].set_xlabel("time from top of flight [s]")
    axes[-1, 1].set_xlabel("time from top of flight [s]")
    g = cmp.gait
    fig.suptitle(
        f"Periodic half cycle at {g.speed:g} m/s (TOF to TOF, stance shaded): tau_SS = {cmp.stance:.3f} s, "
        f"tau_F = {cmp.flight:.3f} s, h = {cmp.height:.3f} m, T_r = {cmp.T_r:.4f} s\n"
        f"time: SLIP optimise+integrate {cmp.slip_time_s * 1e3:.1f} ms, T_r solve "
        f"{cmp.tvlip_time_s * 1e3:.3f} ms, ratio {cmp.ratio:.0f}x (paper: 24.9 s / 8 ms)",
        fontsize=9,
    )
    fig.tight_layout()
    return fig


def save(cmp: SlipComparison, path: str | Path) -> Path:
    """Write :func:`figure` to ``path`` (format from the suffix), atomically."""
    return save_figure(figure(cmp), path, bbox_inches=None)
