"""Measure the G1's closed-loop limits in MuJoCo (issue 5): largest lateral push and top speed.

    .venv/bin/python benchmarks/sim_limits.py [--pushes 10 11 12 13 14 15] [--strides 0.50 0.55 0.60]

* Push: ``g1-push-recovery`` with a lateral impulse (N s) at mid-stance of steps 4 (+y) and 8 (-y);
  the largest impulse survived without a fall is reported.
* Top speed: ``g1-top-speed`` with the constant stride swept; for each stride the planned speed is
  stride / (tau_SS + tau_F), and the measured mean forward CoM speed over the constant-stride steps is
  reported; the top speed is the fastest plan held for all 10 constant steps without a fall.
Writes benchmarks/sim_limits.json.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import numpy as np

os.environ.setdefault("MUJOCO_GL", "egl")

import gaitshift  # noqa: E402
from gaitshift.scenario import builtin_text, load_scenario  # noqa: E402
from gaitshift.sim.loop import SimOptions, mid_stance_pushes, simulate  # noqa: E402

import yaml  # noqa: E402


def push_sweep(impulses):
    traj = gaitshift.plan(load_scenario("g1-push-recovery"))
    rows = []
    for j in impulses:
        t0 = time.perf_counter()
        res = simulate(traj, SimOptions(pushes=mid_stance_pushes(traj, j)))
        rows.append({"impulse_Ns": j, "fell": bool(res.fell), "fall_time": float(res.fall_time),
                     "wall_s": time.perf_counter() - t0})
        print(f"push {j:5.1f} N s: {'FELL at %.2f s' % res.fall_time if res.fell else 'survived'}", flush=True)
    ok = [r["impulse_Ns"] for r in rows if not r["fell"]]
    return rows, (max(ok) if ok else None)


def speed_sweep(strides):
    base = yaml.safe_load(builtin_text("g1-top-speed"))
    rows = []
    for s in strides:
        data = dict(base, profile=dict(base["profile"], max_stride=s), name=f"g1-top-speed-{s}")
        sc = load_scenario(data)
        traj = gaitshift.plan(sc)
        res = simulate(traj)
        planned = s / (sc.timing.single_support + sc.timing.flight)
        # constant-stride steps: footholds whose stride equals the maximum
        fs = traj.footsteps[2:-1, 0]
        stride = np.diff(np.r_[0.0, fs])
        const = np.flatnonzero(np.isclose(stride, stride.max(), atol=1e-9))
        a = res.arrays
        t_land = [traj.t[np.argmax(traj.contact[:, traj.footstep_side[2 + i]] &
                                   (np.abs(traj.foot_pos[:, traj.footstep_side[2 + i], 0] - fs[i]) < 1e-9))]
                  for i in (const[0], const[-1])]
        m = (a["t"] >= t_land[0]) & (a["t"] <= t_land[1])
        measured = float(np.mean(a["com_vel"][m, 0])) if m.any() and not res.fell else float("nan")
        rows.append({"stride_m": s, "planned_speed": planned, "fell": bool(res.fell),
                     "fall_time": float(res.fall_time), "measured_mean_speed": measured})
        print(f"stride {s:.2f} m ({planned:.2f} m/s planned): "
              f"{'FELL at %.2f s' % res.fall_time if res.fell else 'held, measured %.2f m/s' % measured}", flush=True)
    ok = [r["planned_speed"] for r in rows if not r["fell"]]
    return rows, (max(ok) if ok else None)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pushes", type=float, nargs="*", default=[10, 11, 12, 13, 14, 15])
    ap.add_argument("--strides", type=float, nargs="*", default=[0.50, 0.55, 0.60])
    ap.add_argument("--out", type=Path, default=Path(__file__).with_name("sim_limits.json"))
    args = ap.parse_args()
    push_rows, push_max = push_sweep(args.pushes)
    speed_rows, top = speed_sweep(args.strides)
    out = {"pushes": push_rows, "largest_push_survived_Ns": push_max,
           "speeds": speed_rows, "top_speed_held_m_s": top}
    args.out.write_text(json.dumps(out, indent=2))
    print(f"largest push survived: {push_max} N s; top speed held for 10 steps: {top} m/s -> {args.out}")


if __name__ == "__main__":
    main()
