"""Measure the G1's closed-loop limits in MuJoCo (issues 5, 13, 17): largest pushes while running, top
speed, and the sensing targets, each with the estimated and the oracle state side by side.

    .venv/bin/python benchmarks/sim_limits.py [--patterns lateral forward backward] [--gains 1 0]
        [--speeds 1.8 2.0 2.05 2.1 2.2] [--fixed-timing] [--no-speed] [--no-pushes]
        [--states estimated oracle] [--envelope] [--sensing] [--only-sensing]

``--envelope`` adds the pass/fail rows of issue 13 (docs/simulation.md): turning while running
(g1-run-turn), stairs up and down, the running step, the four slopes, and mass -10 % / +10 %, floor
friction 0.4 and a 1-tick delay, each alone on g1-walk-run-walk.

``--sensing`` adds the rows of issue 17 (docs/estimation.md): every shipped G1 scenario at default
settings; the estimation errors on g1-walk-run-walk; floor friction 0.35 with the controller not told;
a 4-tick latency (with and without prediction); the largest ``rl-peer`` noise scale held, by bisection.

* Push: ``g1-push-recovery`` (12 running steps) with impulses (N s, 0.1 s) at mid-stance (single
  support) of running steps 4 and 8: ``lateral`` +y then -y, ``forward`` +x twice, ``backward`` -x
  twice; the largest impulse survived without a fall, with the legs never touching each other and the
  feet never passing through each other (``legs_touch_time`` and ``feet_overlap_time`` 0:
  :mod:`gaitshift.sim.leg_clearance`), is found by bisection (0.5 N s; the upper end
  starts at 48 N s and doubles while survived), with the step adjustment
  (:mod:`gaitshift.control.feedback`) at its default gain (1) and off (gain 0).
* Top speed: ``g1-top-speed`` with the planned speed v swept; each run takes the running timing of the
  robot's timing law at v (``gaitshift.gait.run_timing``: stance <= run_contact_length / v, swing time
  kept; ``--fixed-timing``: g1-run's 0.32 / 0.12 s at every speed) and the stride v (T_s + T_f);
  the measured mean forward CoM speed over the constant-stride steps is reported; the top speed is the
  fastest plan held for all 10 constant steps without a fall (and, reported beside it, the fastest
  held with the legs never touching each other).
Writes benchmarks/sim_limits.json.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

os.environ.setdefault("MUJOCO_GL", "egl")

import yaml

import gaitshift
from gaitshift.common.atomic import atomic_path
from gaitshift.common.jsonsafe import finite_json
from gaitshift.control.feedback import CaptureSettings
from gaitshift.gait.run_timing import running_timing
from gaitshift.robots.config import load_robot
from gaitshift.scenario.loader import builtin_names, builtin_text, load_scenario
from gaitshift.sim.loop import SimOptions, simulate
from gaitshift.sim.pushes import mid_stance_pushes
from gaitshift.sim.scenario_run import simulate_scenario


def push_survived(traj, impulse, pattern, state, gain):
    """One run of ``traj`` with mid-stance pushes of ``impulse`` N s (``pattern`` of
    :data:`gaitshift.sim.pushes.PATTERNS`) and the step adjustment gain ``gain`` (0: off): whether it
    was survived cleanly (no fall, the legs clear of each other), whether it fell, the fall time (s,
    nan without a fall) and the legs' contact and overlap times, s."""
    opts = SimOptions(
        pushes=mid_stance_pushes(traj, impulse, pattern=pattern),
        state=state,
        capture=replace(CaptureSettings(), gain=gain),
    )
    res = simulate(traj, opts)
    touch, overlap = res.metrics["legs_touch_time"], res.metrics["feet_overlap_time"]
    return not res.fell and touch == 0.0 and overlap == 0.0, bool(res.fell), float(res.fall_time), touch, overlap


def push_bisection(pattern, state, gain, lo=0.0, hi=48.0, tol=0.5, cap=192.0):
    """Largest impulse (N s) survived on g1-push-recovery (pushes at mid-stance of running steps 4 and
    8), by bisection in [lo, hi] to ``tol``: ``lo`` is assumed survived; ``hi`` is checked first and
    doubled while it is survived (up to ``cap``, then reported as a lower bound)."""
    traj = gaitshift.plan(load_scenario("g1-push-recovery"))
    rows = []

    def probe(j):
        t0 = time.perf_counter()
        ok, fell, fall, touch, overlap = push_survived(traj, j, pattern, state, gain)
        rows.append(
            {
                "impulse_Ns": j,
                "held": ok,
                "fell": fell,
                "fall_time": fall,
                "legs_touch_s": touch,
                "feet_overlap_s": overlap,
                "wall_s": time.perf_counter() - t0,
            }
        )
        clash = f"legs touch {touch:.3f} s, feet overlap {overlap:.3f} s"
        how = "ok" if ok else (f"FELL at {fall:.2f} s" if fell else clash)
        print(f"  {pattern:8s} {state:9s} gain {gain:g}: {j:6.2f} N s {how}", flush=True)
        return ok

    while probe(hi):
        if hi >= cap:
            return rows, hi
        lo, hi = hi, 2.0 * hi
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if probe(mid) else (lo, mid)
    return rows, lo


def push_table(states, gains, patterns=("lateral", "forward", "backward")):
    """Largest push survived while running, per direction, state source and step adjustment gain."""
    out = []
    for pattern in patterns:
        for state in states:
            for gain in gains:
                rows, best = push_bisection(pattern, state, gain)
                out.append({"pattern": pattern, "state": state, "gain": gain, "largest_Ns": best, "runs": rows})
                print(f"{pattern:8s} {state:9s} step adjustment gain {gain:g}: largest {best:.2f} N s", flush=True)
    return out


def speed_sweep(speeds, state="oracle", law=True):
    """For each planned speed v: the g1-top-speed run at v with the running timing of the robot's law
    (:func:`gaitshift.gait.run_timing.running_timing` from g1-run's nominal timing; ``law=False``: that
    nominal timing at every speed) and the stride v (T_s + T_f)."""
    base = yaml.safe_load(builtin_text("g1-top-speed"))
    contact = load_robot(base["robot"]).run_contact_length if law else float("inf")
    t0 = yaml.safe_load(builtin_text("g1-run"))["timing"]  # the nominal running timing of the law
    rows = []
    for v in speeds:
        ts, tf = (float(x) for x in running_timing(v, t0["single_support"], t0["flight"], contact))
        s = round(v * (ts + tf), 4)
        data = dict(
            base,
            timing=dict(t0, single_support=round(ts, 4), flight=round(tf, 4)),
            profile=dict(base["profile"], max_stride=s),
            name=f"g1-top-speed-{v}",
        )
        sim = simulate_scenario(load_scenario(data), state=state)
        sc, traj, res = sim.scenario, sim.plan, sim.result
        planned = round(s / (sc.timing.single_support + sc.timing.flight), 3)
        # constant-stride steps: footholds whose stride equals the maximum
        fs = traj.footsteps[2:-1, 0]
        stride = np.diff(np.r_[0.0, fs])
        const = np.flatnonzero(np.isclose(stride, stride.max(), atol=1e-9))
        a = res.arrays
        t_land = [
            traj.t[
                np.argmax(
                    traj.contact[:, traj.footstep_side[2 + i]]
                    & (np.abs(traj.foot_pos[:, traj.footstep_side[2 + i], 0] - fs[i]) < 1e-9)
                )
            ]
            for i in (const[0], const[-1])
        ]
        m = (a["t"] >= t_land[0]) & (a["t"] <= t_land[1])
        measured = float(np.mean(a["com_vel"][m, 0])) if m.any() and not res.fell else float("nan")
        rows.append(
            {
                "stride_m": s,
                "single_support": sc.timing.single_support,
                "flight": sc.timing.flight,
                "planned_speed": planned,
                "fell": bool(res.fell),
                "fall_time": float(res.fall_time),
                "measured_mean_speed": measured,
                "legs_touch_s": res.metrics["legs_touch_time"],
                "feet_overlap_s": res.metrics["feet_overlap_time"],
            }
        )
        clash = (
            f"legs touch {res.metrics['legs_touch_time']:.3f} s, feet overlap {res.metrics['feet_overlap_time']:.3f} s"
        )
        print(
            f"{planned:.2f} m/s planned (stride {s:.3f} m, SS {ts:.3f} s, flight {tf:.3f} s): "
            f"{f'FELL at {res.fall_time:.2f} s' if res.fell else f'held, measured {measured:.2f} m/s'}; {clash}",
            flush=True,
        )
    ok = [r["planned_speed"] for r in rows if not r["fell"]]
    clean = [r["planned_speed"] for r in rows if not r["fell"] and r["legs_touch_s"] == r["feet_overlap_s"] == 0.0]
    return rows, (max(ok) if ok else None), (max(clean) if clean else None)


def run(name, **kw):
    """One closed-loop run of scenario ``name`` (re-planned if it is an online or locomotion plan)."""
    res = simulate_scenario(name, **kw).result
    m = res.metrics
    row = {"scenario": name, **kw, "fell": bool(res.fell), "fall_time": float(res.fall_time)}
    row["estimation"] = m["estimation"]
    e = m["estimation"]
    how = f"FELL at {res.fall_time:.2f} s" if res.fell else "no fall"
    print(
        f"{name:28s} {kw}: {how}; vel {e['base_vel_rmse']:.3f} "
        f"tilt {e['tilt_rmse']:.4f} yaw {e['yaw_drift']:.3f} drift/m {e['pos_drift_per_m'] or float('nan'):.4f} "
        f"contact {e['contact_accuracy']:.3f} tick {e['tick_us']:.0f} us",
        flush=True,
    )
    return row


def noise_bisection(state, lo=0.0, hi=2.0, iters=4):
    """Largest rl-peer scale held on g1-walk-run-walk (bisection in [lo, hi], ``iters`` halvings)."""
    rows = []
    if not run("g1-walk-run-walk", state=state, noise="rl-peer", noise_scale=hi)["fell"]:
        return rows, hi
    for _ in range(iters):
        mid = 0.5 * (lo + hi)
        r = run("g1-walk-run-walk", state=state, noise="rl-peer", noise_scale=mid)
        rows.append(r)
        lo, hi = (mid, hi) if not r["fell"] else (lo, mid)
    return rows, lo


def sensing_rows(states):
    """The rows of issue 17's target table, per state source."""
    out = {}
    g1 = [n for n in builtin_names() if n.startswith("g1-")]
    for state in states:
        rows = {"scenarios": [run(n, state=state) for n in g1]}
        rows["friction_0.35_not_told"] = run("g1-walk-run-walk", state=state, friction=0.35)
        rows["latency_4"] = run("g1-walk-run-walk", state=state, latency=4)
        rows["latency_4_no_prediction"] = run("g1-walk-run-walk", state=state, latency=4, predict_latency=False)
        rows["latency_3_no_prediction"] = run("g1-walk-run-walk", state=state, latency=3, predict_latency=False)
        rows["rl_peer"], rows["rl_peer_largest_scale_held"] = noise_bisection(state)
        out[state] = rows
    return out


#: issue 13's table rows that are a pass/fail run, not a bisection: the scenario and the options
ENVELOPE_ROWS = (
    ("turning while running, 1.5 m/s at 0.5 rad/s", "g1-run-turn", {}),
    ("stairs up, walking, 10 cm", "g1-stairs-up", {}),
    ("stairs down, walking, 10 cm", "g1-stairs-down", {}),
    ("running over a 5 cm step", "g1-run-step", {}),
    ("slope +10 deg, walking", "g1-slope-up", {}),
    ("slope -10 deg, walking", "g1-slope-down", {}),
    ("slope +10 deg, running", "g1-run-slope-up", {}),
    ("slope -10 deg, running", "g1-run-slope-down", {}),
    ("mass -10 %, g1-walk-run-walk", "g1-walk-run-walk", {"mass_scale": 0.9}),
    ("mass +10 %, g1-walk-run-walk", "g1-walk-run-walk", {"mass_scale": 1.1}),
    ("floor friction 0.4, g1-walk-run-walk", "g1-walk-run-walk", {"friction": 0.4}),
    ("1-tick delay, g1-walk-run-walk", "g1-walk-run-walk", {"latency": 1}),
)


def envelope_rows(states):
    """Issue 13's pass/fail rows (terrain, turning while running, each perturbation alone), per state."""
    return [{"row": label, **run(name, state=state, **kw)} for state in states for label, name, kw in ENVELOPE_ROWS]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--patterns", nargs="*", default=["lateral", "forward", "backward"])
    ap.add_argument("--gains", type=float, nargs="*", default=[1.0, 0.0], help="step adjustment gains (0: off)")
    ap.add_argument("--no-pushes", action="store_true", help="skip the push bisections")
    ap.add_argument("--no-speed", action="store_true", help="skip the top-speed sweep")
    ap.add_argument("--speeds", type=float, nargs="*", default=[1.8, 2.0, 2.05, 2.1, 2.2])
    ap.add_argument("--fixed-timing", action="store_true", help="the scenario's timing at every speed")
    ap.add_argument("--states", nargs="*", default=["estimated", "oracle"])
    ap.add_argument("--sensing", action="store_true", help="also measure issue 17's sensing rows")
    ap.add_argument("--envelope", action="store_true", help="also run issue 13's pass/fail rows (terrain, ...)")
    ap.add_argument("--only-sensing", action="store_true", help="only issue 17's sensing rows")
    ap.add_argument("--out", type=Path, default=Path(__file__).with_name("sim_limits.json"))
    args = ap.parse_args()
    out = {}
    if not args.only_sensing:
        if not args.no_pushes:
            out["pushes"] = push_table(args.states, args.gains, args.patterns)
        for state in [] if args.no_speed else args.states:
            speed_rows, top, clean = speed_sweep(args.speeds, state, law=not args.fixed_timing)
            out[state] = {"speeds": speed_rows, "top_speed_held_m_s": top, "top_speed_held_legs_clear_m_s": clean}
            print(f"{state}: top speed held for 10 steps {top} m/s ({clean} m/s with the legs never touching)")
    if args.envelope and not args.only_sensing:
        out["envelope"] = envelope_rows(args.states)
    if args.sensing or args.only_sensing:
        out["sensing"] = sensing_rows(args.states)
    with atomic_path(args.out) as tmp:  # strict JSON: a NaN (no fall, no speed measured) is null
        tmp.write_text(json.dumps(finite_json(out), indent=2, default=str, allow_nan=False))
    print(f"-> {args.out}")


if __name__ == "__main__":
    main()
