"""A scenario over DDS under link faults (docs/deploy.md, "Faults on the link"): ``gaitshift dds robot`` and
``gaitshift dds control`` as two processes on the loopback, one fresh domain per run, in lockstep (the
robot steps once per command: a loaded machine slows the run, it does not change it), once per fault
configuration. A row per run: the brain's exit, phase and reason; the robot's fall, the distance its pelvis
walked against the plan's; the link's counts; the brain's estimate as the robot scored it; the brain's tick
times (lockstep: the brain's own compute per tick, not a real-time figure). The stale limit is 0.5 s: in
lockstep the wall clock measures the machine's load, not the link. The brain re-plans inline by default
(``--replan``): in lockstep a tick may take its time, and the runs do not depend on the load (the off-tick
worker's plans come later the busier the machine, a real-time matter: docs/deploy.md "Real time").
``--real-time``: both processes on the wall clock instead (the robot in its gantry until the brain's first
command, the brain's stale limit and ``--latency`` their defaults, the re-plans ``--replan`` as given): the
tick figures are then real-time ones, and a run depends on the machine's load.

    PYTHONPATH=src .venv/bin/python benchmarks/dds_faults.py [SCENARIO] [--noise typical] [--domain 120]
        [--only clean drop ...] [--latency TICKS] [--replan inline] [--seed 1] [--real-time] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

#: name -> the robot process's link flags
FAULTS = {
    "clean": [],
    "drop 5 %": ["--drop", "0.05"],
    "delay 4 +- 1 ms": ["--delay-ms", "4", "--jitter-ms", "1"],
    "corrupt 2 %": ["--corrupt", "0.02"],
    "all three": ["--drop", "0.05", "--delay-ms", "4", "--jitter-ms", "1", "--corrupt", "0.02"],
}
CODE = "from gaitshift.cli import main; main()"


def run(
    scenario: str,
    name: str,
    domain: int,
    noise: str,
    folder: Path,
    latency: int | None = None,
    replan: str = "inline",
    seed: int = 1,
    real_time: bool = False,
) -> dict:
    """One run of the pair (module docstring): both summaries and the wall time."""
    env = {**os.environ, "MUJOCO_GL": "egl"}
    robot_json = folder / f"robot-{domain}.json"
    pace = [] if real_time else ["--lockstep"]
    robot_cmd = ["dds", "robot", "g1", "--domain", str(domain), *pace, "--noise", noise]
    robot_cmd += ["--summary", str(robot_json), "--world", scenario, "--seed", str(seed), *FAULTS[name]]
    brain_cmd = ["dds", "control", scenario, "--domain", str(domain), *pace, "--json", "--replan", replan]
    brain_cmd += [] if real_time else ["--stale-limit", "0.5"]
    brain_cmd += [] if latency is None else ["--latency", str(latency)]
    start = time.perf_counter()
    with open(folder / f"robot-{domain}.err", "w") as rerr:
        robot = subprocess.Popen([sys.executable, "-c", CODE, *robot_cmd], stderr=rerr, env=env)
        brain = subprocess.run(
            [sys.executable, "-c", CODE, *brain_cmd], check=False, capture_output=True, text=True, env=env
        )
        robot.terminate()
        robot.wait(timeout=60)
    wall = time.perf_counter() - start
    b = json.loads(brain.stdout) if brain.stdout.strip() else {}
    r = json.loads(robot_json.read_text()) if robot_json.exists() else {}
    name += f", brain --latency {latency}" if latency is not None else ""
    return {"fault": name, "exit": brain.returncode, "stderr": brain.stderr.strip().splitlines()[-1:], "brain": b,
            "robot": r, "wall_s": wall}  # fmt: skip


def row(res: dict) -> str:
    """Markdown row of one run."""
    b, r = res["brain"], res["robot"]

    def f(d: dict, key: str, fmt: str = ".4f") -> str:
        v = d.get(key)
        return "-" if v is None else format(v, fmt)

    fell = f"at {r['fall_time']:.2f} s" if r.get("fell") else "no"
    return (
        f"| {res['fault']} | {res['exit']} ({b.get('phase', '?')}: {b.get('reason', '')}) | {fell} | "
        f"{f(r, 'distance', '.2f')} / {f(b, 'planned_distance', '.2f')} | {r.get('link_dropped', 0)} / "
        f"{r.get('link_corrupted', 0)} / {b.get('states_measured_only', 0)} / {f(r, 'link_delay_ticks_mean', '.2f')} | "
        f"{b.get('states_dropped', '-')} | "
        f"{f(r, 'est_velocity_rmse')} | {f(r, 'est_tilt_rmse')} | {f(r, 'est_contact_accuracy', '.3f')} | "
        f"{f(b, 'tick_p50_ms', '.2f')} / {f(b, 'tick_p99_ms', '.2f')} / {f(b, 'tick_p999_ms', '.2f')} | "
        f"{res['wall_s']:.0f} |"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scenario", nargs="?", default="g1-tour")
    ap.add_argument("--noise", default="typical")
    ap.add_argument("--domain", type=int, default=120)
    ap.add_argument("--only", nargs="+", choices=list(FAULTS), default=list(FAULTS))
    ap.add_argument("--latency", type=int, default=None, help="the brain's --latency (default: the brain's)")
    ap.add_argument("--replan", default="inline", help="the brain's --replan (lockstep: inline is deterministic)")
    ap.add_argument("--seed", type=int, default=1, help="the robot process's --seed (its noise and link faults)")
    ap.add_argument("--real-time", action="store_true", help="both on the wall clock instead of lockstep")
    ap.add_argument("--json", type=Path)
    args = ap.parse_args()
    results = []
    print(
        "| link | brain exit | robot fell | distance / planned m "
        "| dropped / corrupted / measured only / mean delay ticks "
        "| brain CRC drops | est. vel RMSE m/s | est. tilt RMSE rad | est. contact | brain tick p50 / p99 / p99.9 ms "
        "| wall s |\n|---|---|---|---|---|---|---|---|---|---|---|",
        flush=True,
    )
    with tempfile.TemporaryDirectory() as tmp:
        for i, name in enumerate(args.only):
            res = run(
                args.scenario, name, args.domain + i, args.noise, Path(tmp), args.latency, args.replan, args.seed,
                args.real_time,
            )  # fmt: skip
            results.append(res)
            print(row(res), flush=True)
    if args.json:
        args.json.write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
