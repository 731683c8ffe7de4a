"""Figures of a closed-loop run (matplotlib, Agg backend).

* ``sim_com_grf.png``: CoM height and total vertical ground reaction force, reference (the plan:
  ``m (g + z''_ref)``) and simulated (sum of MuJoCo contact forces), as Figs. 11 and 13 of paper 001;
* ``sim_speed.png``: planned, simulated and commanded forward CoM speed (Fig. 7 of paper 003);
* ``sim_snapshots.png``: rendered snapshots at evenly spaced times (needs an OpenGL context, e.g.
  MUJOCO_GL=egl; skipped with a note when none is available);
* ``sim_estimation.png``: the state estimate against the truth (:mod:`gaitshift.plots.estimation`),
  when the run logged the estimator;
* ``sim_perception.png``: the controller's elevation map as the run ended (:mod:`gaitshift.plots.perception`),
  when the robot has a depth camera.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from gaitshift.common.runs import true_runs
from gaitshift.plots.estimation import KEYS as ESTIMATION_KEYS
from gaitshift.plots.estimation import plot_estimation
from gaitshift.plots.files import save_figure


def _save(fig: Any, path: Path) -> Path:
    return save_figure(fig, path, format="png", dpi=110, bbox_inches=None)


def plot_com_grf(result: Any, traj: Any, path: Path, mass: float) -> Path:
    a = result.arrays
    t = a["t"]
    i = a["plan_index"]
    g = traj.gravity
    fig, ax = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
    ax[0].plot(t, a["com_ref"][:, 2], "k--", lw=1.2, label="reference (plan)")
    ax[0].plot(t, a["com_pos"][:, 2], "C0", lw=1.0, label="simulated")
    ax[0].set_ylabel("CoM z [m]")
    ax[0].legend(loc="best")
    fz_ref = mass * (g + traj.com_acc[i, 2])
    ax[1].plot(t, fz_ref, "k--", lw=1.2, label="reference m (g + z'')")
    ax[1].plot(t, a["grf"][:, :, 2].sum(axis=1), "C3", lw=0.8, label="simulated (contacts)")
    ax[1].set_ylabel("vertical GRF [N]")
    ax[1].set_xlabel("t [s]")
    ax[1].legend(loc="best")
    _shade_flight(ax, t, a["contact_ref"])
    fig.suptitle("Closed loop: CoM height and vertical ground reaction force")
    fig.tight_layout()
    return _save(fig, path)


def _shade_flight(axes: Any, t: np.ndarray, contact: np.ndarray) -> None:
    """Grey bands over the planned flight phases (no foot in contact) on every axis of ``axes``."""
    for s, e in true_runs(~np.any(contact, axis=1)):
        for ax in axes:
            ax.axvspan(t[s], t[e - 1], color="0.9", lw=0)


def plot_speed(result: Any, traj: Any, path: Path) -> Path:
    a = result.arrays
    t = a["t"]
    i = a["plan_index"]
    fig, ax = plt.subplots(figsize=(9, 4))
    ax.plot(t, a["com_vel_ref"][:, 0], "k--", lw=1.2, label="planned")
    ax.plot(t, a["com_vel"][:, 0], "C0", lw=0.9, label="simulated")
    cmd = traj.command_vel[i, 0]
    if np.any(np.isfinite(cmd)):
        ax.plot(t, cmd, "C2", lw=1.5, label="commanded")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("forward CoM speed [m/s]")
    ax.legend(loc="best")
    fig.tight_layout()
    return _save(fig, path)


def plot_snapshots(result: Any, model: Any, path: Path, count: int = 6) -> Path | None:
    import mujoco

    a = result.arrays
    n = len(a["t"])
    if n == 0:
        return None
    try:
        renderer = mujoco.Renderer(model, height=320, width=240)
    except (mujoco.FatalError, RuntimeError, ImportError, OSError, AttributeError):
        return None  # no OpenGL context (no device, no library, wrong PYOPENGL_PLATFORM): no snapshots
    d = mujoco.MjData(model)
    idx = np.linspace(0, n - 1, count).astype(int)
    fig, ax = plt.subplots(1, count, figsize=(2.2 * count, 3.2))
    for axk, k in zip(np.atleast_1d(ax), idx, strict=True):
        d.qpos[:] = a["qpos"][k]
        mujoco.mj_forward(model, d)
        cam = mujoco.MjvCamera()
        cam.type = mujoco.mjtCamera.mjCAMERA_FREE
        cam.lookat[:] = [d.qpos[0], d.qpos[1], 0.55]
        cam.distance, cam.azimuth, cam.elevation = 2.2, 100.0, -10.0
        renderer.update_scene(d, camera=cam)
        axk.imshow(renderer.render())
        axk.set_title(f"t = {a['t'][k]:.2f} s", fontsize=9)
        axk.axis("off")
    renderer.close()
    fig.tight_layout()
    return _save(fig, path)


def plot_all(result: Any, traj: Any, folder: str | Path) -> list[Path]:
    """Write every figure into ``folder``; returns the paths written."""
    from gaitshift.sim.plant import build_plant

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    plant = build_plant(float(result.meta["control_period"]), result.meta.get("robot", "g1"))
    out = [
        plot_com_grf(result, traj, folder / "sim_com_grf.png", plant.mass),
        plot_speed(result, traj, folder / "sim_speed.png"),
    ]
    snap = plot_snapshots(result, plant.model, folder / "sim_snapshots.png")
    if snap is not None:
        out.append(snap)
    if all(key in result.arrays for key in ESTIMATION_KEYS):
        est = result.metrics.get("estimation") if isinstance(result.metrics, dict) else None
        out.append(plot_estimation(result.arrays, folder / "sim_estimation.png", est))
    if "map_heights" in result.arrays:
        from gaitshift.plots.perception import perception_figure

        per = result.metrics.get("perception", {}) if isinstance(result.metrics, dict) else {}
        title = ", ".join(f"{k} {v:.4g}" for k, v in per.items() if isinstance(v, int | float))
        path = folder / "sim_perception.png"
        out.append(perception_figure(result.arrays, path, f"elevation map: {title}", traj.footsteps))
    return out
