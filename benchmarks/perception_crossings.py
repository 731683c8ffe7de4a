"""The crossing table of docs/perception.md: every scenario of ``docs/perception/`` on the G1's estimated
state, the terrain perceived (seeds 0-2), and for comparison known and blind (seed 0).

    PYTHONPATH=src .venv/bin/python benchmarks/perception_crossings.py [--seeds 3] [--workers 2] \
        [--json benchmarks/perception_crossings.json]

Each run is ``gaitshift simulate SCENARIO --terrain KNOWLEDGE --seed S`` (Dask, one process per run); the
table gives whether it fell (when), where the pelvis ended (the terrain lies from x = 1 m or 4 m on:
a robot that stopped before it did not cross it), the map's error under the feet (median, p95), the true
soles' distance from the nearest step edge at touchdown (min, median), the re-plans and the stop.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any

import dask

ROOT = Path(__file__).resolve().parents[1]
SCENARIOS = sorted((ROOT / "docs" / "perception").glob("*.yaml"))


def run_one(path: str, knowledge: str, seed: int) -> dict[str, Any]:
    """One closed-loop run's row."""
    from gaitshift.sim.scenario_run import simulate_scenario

    t0 = time.perf_counter()
    run = simulate_scenario(path, terrain=knowledge, seed=seed)
    m, p = run.result.metrics, run.result.metrics.get("perception", {})
    drv = run.driver
    return {
        "scenario": Path(path).stem,
        "terrain": knowledge,
        "seed": seed,
        "fell": bool(m["fell"]),
        "fall_time": m.get("fall_time"),
        "steps": f"{m['steps_completed']}/{m['steps_planned']}",
        "end_x": float(run.result.arrays["qpos"][-1, 0]),
        "map_error_median": p.get("map_error_median"),
        "map_error_p95": p.get("map_error_p95"),
        "frame_error_median": p.get("frame_error_median"),
        "frame_error_p95": p.get("frame_error_p95"),
        "edge_distance_min": p.get("edge_distance_min"),
        "edge_distance_median": p.get("edge_distance_median"),
        "replans": getattr(drv, "replans", 0),
        "refused": getattr(drv, "refused", 0),
        "stopped": p.get("stopped"),
        "wall_s": time.perf_counter() - t0,
    }


def _mm(v: Any) -> str:
    return "-" if v is None else f"{1e3 * v:.1f}"


def table(rows: list[dict[str, Any]]) -> str:
    """The markdown table of the rows."""
    out = [
        "| scenario | terrain | seed | result | map error median / p95, mm | edge distance min / median, mm "
        "| re-plans |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        result = f"falls at {r['fall_time']:.2f} s" if r["fell"] else "no fall"
        result += f", pelvis ends at x = {r['end_x']:.2f} m"
        if r["stopped"]:
            result += f"; {r['stopped']}"
        out.append(
            f"| {r['scenario']} | {r['terrain']} | {r['seed']} | {result} | "
            f"{_mm(r['map_error_median'])} / {_mm(r['map_error_p95'])} | "
            f"{_mm(r['edge_distance_min'])} / {_mm(r['edge_distance_median'])} | {r['replans']} |"
        )
    return "\n".join(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args()
    jobs = [(str(p), "perceived", s) for p in SCENARIOS for s in range(args.seeds)]
    jobs += [(str(p), k, 0) for p in SCENARIOS for k in ("known", "blind")]
    t0 = time.perf_counter()
    rows = list(
        dask.compute(*(dask.delayed(run_one)(*j) for j in jobs), scheduler="processes", num_workers=args.workers)
    )
    rows.sort(key=lambda r: (r["scenario"], ("perceived", "known", "blind").index(r["terrain"]), r["seed"]))
    print(table(rows))
    print(f"\n{len(rows)} runs in {time.perf_counter() - t0:.0f} s with {args.workers} workers")
    if args.json is not None:
        args.json.write_text(json.dumps(rows, indent=1) + "\n")


if __name__ == "__main__":
    main()
