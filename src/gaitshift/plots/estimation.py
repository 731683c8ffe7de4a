"""The state estimate against the truth over a closed-loop run (issue 17): ``sim_estimation.png``.

From a run's arrays (:class:`gaitshift.sim.result.SimResult`, or the ``.npz`` that ``gaitshift simulate
--out`` writes): the truth ``qpos``, ``qvel`` (floating base first: position, quaternion (w, x, y, z);
world-frame linear velocity), ``contact`` and ``grf``; the estimate ``est_qpos``, ``est_qvel``,
``est_contact`` in the same conventions (:mod:`gaitshift.sim.estimation_metrics`). Four panels, truth
solid and estimate dashed:

* base velocity, x, y, z (m/s);
* base roll and pitch (rad) and the yaw error ``yaw_hat - yaw`` wrapped to (-pi, pi];
* horizontal base position, x and y (m);
* contact per sole: truth (a nonzero normal force, as the ``contact_accuracy`` metric counts it) and
  the estimated flags, offset for reading.

The title carries the run's ``estimation`` metrics (base velocity and tilt RMSE, yaw drift, position
drift per metre, contact accuracy).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from gaitshift.common.rotations import roll_pitch_yaw
from gaitshift.errors import InputError
from gaitshift.plots.files import save_figure
from gaitshift.trajectory.formats import NPZ_ERRORS

#: the arrays the figure reads
KEYS = ("t", "qpos", "qvel", "contact", "grf", "est_qpos", "est_qvel", "est_contact")


def estimate_vs_truth(a: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The series the figure draws (module docstring), each (K, ...) over the run's K ticks: ``t``;
    ``vel``, ``vel_hat`` (K, 3) m/s; ``rpy``, ``rpy_hat`` (K, 3) rad; ``yaw_error`` (K,) rad wrapped to
    (-pi, pi]; ``pos``, ``pos_hat`` (K, 2) m; ``contact``, ``contact_hat`` (K, 2) bool."""
    rpy, rpy_hat = roll_pitch_yaw(a["qpos"][:, 3:7]), roll_pitch_yaw(a["est_qpos"][:, 3:7])
    dyaw = rpy_hat[:, 2] - rpy[:, 2]
    return {
        "t": a["t"],
        "vel": a["qvel"][:, :3],
        "vel_hat": a["est_qvel"][:, :3],
        "rpy": rpy,
        "rpy_hat": rpy_hat,
        "yaw_error": np.pi - np.remainder(np.pi - dyaw, 2 * np.pi),
        "pos": a["qpos"][:, :2],
        "pos_hat": a["est_qpos"][:, :2],
        "contact": a["contact"] & (a["grf"][:, :, 2] > 0.0),
        "contact_hat": a["est_contact"].astype(bool),
    }


def _title(e: dict[str, Any] | None) -> str:
    """The figure's title: the run's ``estimation`` metrics (:mod:`gaitshift.sim.estimation_metrics`)."""
    if not e or not all(isinstance(e.get(k), int | float) for k in ("base_vel_rmse", "tilt_rmse", "yaw_drift")):
        return "state estimate (dashed) against the truth (solid)"
    drift, contact = e.get("pos_drift_per_m"), e.get("contact_accuracy")
    return (
        f"estimate (dashed) vs truth: base velocity RMSE {e['base_vel_rmse']:.3f} m/s, tilt RMSE "
        f"{e['tilt_rmse']:.4f} rad, yaw drift {e['yaw_drift']:.3f} rad, position drift "
        + ("-" if not isinstance(drift, int | float) else f"{100 * drift:.2f} %")
        + ("" if not isinstance(contact, int | float) else f", contact {100 * contact:.1f} %")
    )


def plot_estimation(a: dict[str, np.ndarray], path: str | Path, metrics: dict[str, Any] | None = None) -> Path:
    """Write the figure of the module docstring for the run arrays ``a`` to ``path`` (PNG); ``metrics``:
    the run's ``estimation`` metrics for the title (None: no numbers)."""
    s = estimate_vs_truth(a)
    t = s["t"]
    fig, ax = plt.subplots(4, 1, figsize=(10, 11), sharex=True)
    for k, (name, colour) in enumerate(zip("xyz", ("C0", "C1", "C2"), strict=True)):
        ax[0].plot(t, s["vel"][:, k], colour, lw=1.0, label=f"v{name}")
        ax[0].plot(t, s["vel_hat"][:, k], colour, lw=1.0, ls="--")
    ax[0].set_ylabel("base velocity (m/s)")
    for k, name in enumerate(("roll", "pitch")):
        ax[1].plot(t, s["rpy"][:, k], f"C{k}", lw=1.0, label=name)
        ax[1].plot(t, s["rpy_hat"][:, k], f"C{k}", lw=1.0, ls="--")
    ax[1].plot(t, s["yaw_error"], "C3", lw=1.0, label="yaw error")
    ax[1].set_ylabel("base attitude (rad)")
    for k, name in enumerate("xy"):
        ax[2].plot(t, s["pos"][:, k], f"C{k}", lw=1.0, label=f"base {name}")
        ax[2].plot(t, s["pos_hat"][:, k], f"C{k}", lw=1.0, ls="--")
    ax[2].set_ylabel("base position (m)")
    for k, name in enumerate(("left", "right")):
        ax[3].step(t, s["contact"][:, k] + 2.2 * k, f"C{k}", lw=1.0, where="post", label=f"{name} sole")
        ax[3].step(t, 0.1 + s["contact_hat"][:, k] + 2.2 * k, f"C{k}", lw=1.0, ls="--", where="post")
    ax[3].set_yticks([0, 1, 2.2, 3.2], ["left off", "left on", "right off", "right on"])
    ax[3].set_xlabel("time (s)")
    for axis in ax:
        axis.legend(loc="upper right", fontsize=8)
        axis.grid(alpha=0.3)
    fig.suptitle(_title(metrics), fontsize=9)
    fig.tight_layout()
    return save_figure(fig, path, format="png", dpi=110, bbox_inches=None)


def is_simulation_log(path: str | Path) -> bool:
    """Whether ``path`` is a readable .npz written by ``gaitshift simulate --out`` (its ``qpos``,
    ``fell`` and ``meta`` entries), as opposed to a plan."""
    path = Path(path)
    if path.suffix.lower() != ".npz" or not path.is_file():
        return False
    try:
        with np.load(path, allow_pickle=False) as z:
            return {"qpos", "fell", "meta"} <= set(z.files)
    except NPZ_ERRORS:
        return False


def read_estimation_log(path: str | Path) -> tuple[dict[str, np.ndarray], dict[str, Any] | None]:
    """The arrays of a simulation log that the figure reads (:data:`KEYS`), checked: present, one row
    per tick of ``t`` (at least 2, increasing), finite; and the ``estimation`` metrics its ``meta``
    records (None when it records none).

    Raises:
        InputError: a log without the estimate (``--state oracle`` logs carry it too; an older log may
            not) or with arrays that do not fit.
    """
    allowed = "a simulation log of gaitshift simulate with the estimator's arrays (est_qpos, est_qvel, est_contact)"
    try:
        with np.load(path, allow_pickle=False) as z:
            missing = [k for k in KEYS if k not in z.files]
            a = {k: np.asarray(z[k]) for k in KEYS if k in z.files}
            meta_text = str(z["meta"]) if "meta" in z.files else "{}"
    except NPZ_ERRORS:
        raise InputError("input", str(path), f"{allowed}; this is not a readable .npz") from None
    if missing:
        raise InputError("input", str(path), f"{allowed}; missing {', '.join(missing)}")
    n = len(a["t"])
    shapes = {"qpos": 2, "qvel": 2, "est_qpos": 2, "est_qvel": 2, "contact": 2, "est_contact": 2, "grf": 3}
    fits = n >= 2 and all(a[k].ndim == d and len(a[k]) == n for k, d in shapes.items())
    fits = fits and a["qpos"].shape == a["est_qpos"].shape and a["qpos"].shape[1] >= 7
    numbers = ("t", "qpos", "qvel", "grf", "est_qpos", "est_qvel")
    if not fits or not all(np.all(np.isfinite(a[k])) for k in numbers) or not np.all(np.diff(a["t"]) > 0):
        raise InputError("input", str(path), f"{allowed}, one finite row per tick of an increasing t")
    a["contact"], a["est_contact"] = a["contact"].astype(bool), a["est_contact"].astype(bool)
    try:
        metrics = json.loads(meta_text).get("metrics", {}).get("estimation")
    except (ValueError, AttributeError):
        metrics = None
    return a, metrics if isinstance(metrics, dict) else None
