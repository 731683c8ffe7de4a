"""The figure of docs/perception.md's "Seeing it": a perceived run's recorded scans and re-planned
footholds against the world's true terrain profile.

Runs ``docs/perception/g1-stairs-up-ahead.yaml`` (seed 0, ``--terrain perceived``), or reads a run's
``.npz`` (``gaitshift simulate ... --out``), and draws from its log (what ``--rerun`` records):

* top: the points of a few scans (``scan_points``: placed by the controller with its ESTIMATED
  camera pose) within ``BAND`` m of the path's centre line, in x-z, coloured by the scan's time, over
  the true terrain profile z(x) (black);
* bottom: each set of planned footholds (``footholds``, one set per re-plan that moved them), x and z,
  coloured by the re-plan's time, over the same profile: the blind plan's flat footholds, then the
  ones moved onto the treads.

Usage: ``PYTHONPATH=src .venv/bin/python benchmarks/perception_scan_figure.py [--npz RUN.npz]
[--out docs/figures/perception_scan_stairs_up_ahead.png]``.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from gaitshift.scenario import load_scenario
from gaitshift.scenario.terrain import terrain_of

ROOT = Path(__file__).resolve().parents[1]
SCENARIO = ROOT / "docs" / "perception" / "g1-stairs-up-ahead.yaml"
#: half-width of the band around the path's centre line whose points are drawn, m
BAND = 0.15
#: the plan times whose scans are drawn (the nearest scan to each), s
SCAN_TIMES = (0.0, 2.0, 3.5, 5.0, 7.0)


def run_arrays(npz: Path | None) -> dict[str, Any]:
    """The run's arrays: read from ``npz``, or the scenario simulated (seed 0)."""
    if npz is not None:
        with np.load(npz) as z:
            return {k: z[k] for k in z.files}
    from gaitshift.sim.scenario_run import simulate_scenario

    return simulate_scenario(str(SCENARIO), seed=0).result.arrays


def draw(a: dict[str, Any], out: Path) -> Path:
    """The two panels (module docstring) into ``out`` (PNG)."""
    truth = terrain_of(load_scenario(str(SCENARIO)).terrain)
    x = np.linspace(-0.3, 4.5, 2000)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(9, 7), sharex=True, layout="constrained")
    cmap = plt.get_cmap("plasma")
    t_end = float(a["t"][-1])
    for ts in SCAN_TIMES:
        f = int(np.argmin(np.abs(a["scan_t"] - ts)))
        p = a["scan_points"][a["scan_frame"] == f]
        p = p[np.abs(p[:, 1]) < BAND]
        t_f = float(a["scan_t"][f])
        top.plot(p[:, 0], p[:, 2], ".", ms=3, color=cmap(t_f / t_end), label=f"scan at t = {t_f:.2f} s")
    sets = a["footholds_t"]
    for g, tg in enumerate(sets):
        s = a["footholds"][a["footholds_set"] == g]
        big = g in (0, len(sets) - 1)
        bottom.plot(
            s[:, 0], s[:, 2], "s", ms=7 if big else 4, mfc="none", mew=1.5 if big else 1, color=cmap(tg / t_end)
        )
    for ax in (top, bottom):
        ax.plot(x, truth.height(x), "k-", lw=1, label="true terrain z(x)")
        ax.set_ylabel("z (m)")
        ax.grid(alpha=0.3)
    top.legend(fontsize=7, loc="upper left")
    top.set_title(f"recorded scans within {BAND} m of the path (placed with the estimated camera pose)", fontsize=9)
    bottom.set_title(
        f"planned footholds: {len(sets)} sets (the start's and each re-plan's), first and last large", fontsize=9
    )
    bottom.set_xlabel("x (m)")
    sm = plt.cm.ScalarMappable(cmap=cmap, norm=plt.Normalize(0.0, t_end))
    fig.colorbar(sm, ax=(top, bottom), label="plan time (s)")
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--npz", type=Path, default=None, help="a run of the scenario (else it is simulated)")
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "figures" / "perception_scan_stairs_up_ahead.png")
    args = ap.parse_args()
    print(draw(run_arrays(args.npz), args.out))


if __name__ == "__main__":
    main()
