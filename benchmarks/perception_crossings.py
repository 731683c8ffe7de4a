"""The crossing table of docs/perception.md: the campaign ``docs/campaigns/g1-terrain.yaml`` (every
scenario of ``docs/perception/`` on the G1's estimated state, the terrain known, blind and perceived,
seeds 0-2), run by the campaign engine and printed as the table.

    PYTHONPATH=src .venv/bin/python benchmarks/perception_crossings.py [--out out/g1-terrain] \
        [--workers 2] [--seeds 3] [--json benchmarks/perception_crossings.json]

Each case is ``gaitshift simulate SCENARIO --terrain KNOWLEDGE --seed S`` (the campaign's ``terrain``
axis, one Dask worker process per core given). The cases already in ``--out`` are not run again (the
campaign's resume): pointed at the folder of ``gaitshift campaign docs/campaigns/g1-terrain.yaml --out
DIR`` it prints that run's table. ``--seeds`` other than the spec's 3 runs seeds 0..N-1 into its own
folder. The table gives whether it fell (when), where the pelvis ended (the terrain lies from x = 1 m or
4 m on: a robot that stopped before it did not cross it), the map's error under the feet (median, p95),
the true soles' distance from the nearest step edge at touchdown (min, median), the re-plans and the stop.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any

import yaml

ROOT = Path(__file__).resolve().parents[1]
SPEC = ROOT / "docs" / "campaigns" / "g1-terrain.yaml"
#: the order of the terrains in the table
ORDER = ("perceived", "known", "blind")


def crossing(r: dict[str, Any]) -> dict[str, Any]:
    """One campaign row as a row of the crossing table's JSON."""
    return {
        "scenario": Path(r["scenario"]).stem,
        "terrain": r["terrain"],
        "seed": r["seed"],
        "error": r["error"],
        "fell": r["fell"],
        "fall_time": r["t_fall"],
        "steps": f"{r['steps_completed']}/{r['steps_planned']}",
        "end_x": r["end_x"],
        **{k: r[k] for k in ("map_error_median", "map_error_p95", "frame_error_median", "frame_error_p95")},
        "edge_distance_min": r["edge_distance_min"],
        "edge_distance_median": r["edge_distance_median"],
        "replans": r["replans"],
        "refused": r["replans_refused"],
        "stopped": r["perception_stopped"],
        "wall_s": r["wall_time"],
    }


def _mm(v: Any) -> str:
    return "-" if v is None else f"{1e3 * v:.1f}"


def _result(r: dict[str, Any]) -> str:
    if r["error"] is not None:
        return f"error: {r['error']}"
    result = f"falls at {r['fall_time']:.2f} s" if r["fell"] else "no fall"
    result += f", pelvis ends at x = {r['end_x']:.2f} m"
    return result + (f"; {r['stopped']}" if r["stopped"] else "")


def table(rows: list[dict[str, Any]]) -> str:
    """The markdown table of the rows (:func:`crossing`)."""
    out = [
        "| scenario | terrain | seed | result | map error median / p95, mm | edge distance min / median, mm "
        "| re-plans |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        out.append(
            f"| {r['scenario']} | {r['terrain']} | {r['seed']} | {_result(r)} | "
            f"{_mm(r['map_error_median'])} / {_mm(r['map_error_p95'])} | "
            f"{_mm(r['edge_distance_min'])} / {_mm(r['edge_distance_median'])} | {r['replans']} |"
        )
    return "\n".join(out)


def _spec(seeds: int | None) -> tuple[Any, str]:
    """The campaign spec and its text: the shipped spec, or with seeds 0..``seeds``-1."""
    from gaitshift.campaign.spec import load_spec

    text = SPEC.read_text()
    if seeds is not None:
        data = yaml.safe_load(text)
        data["axes"]["seed"] = list(range(seeds))
        text = yaml.safe_dump(data, sort_keys=False)
    return load_spec(yaml.safe_load(text) | {"base": str(SPEC.parent)}), text


def main() -> None:
    from gaitshift.campaign.run import run_campaign
    from gaitshift.campaign.store import Store

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=None, help="seeds 0..N-1 (default: the spec's, 0-2)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", type=Path, default=None, help="the campaign folder (default: out/g1-terrain[-seedsN])")
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args()
    spec, text = _spec(args.seeds)
    out = args.out or ROOT / "out" / ("g1-terrain" + ("" if args.seeds is None else f"-seeds{args.seeds}"))
    t0 = time.perf_counter()
    summary = run_campaign(spec, text, out, workers=args.workers)
    rows = [crossing(r) for r in Store(out).table().to_pylist()]
    rows.sort(key=lambda r: (r["scenario"], ORDER.index(r["terrain"]), r["seed"]))
    print(table(rows))
    print(f"\n{len(rows)} runs ({summary.ran} now) in {time.perf_counter() - t0:.0f} s with {args.workers} workers")
    if args.json is not None:
        args.json.write_text(json.dumps(rows, indent=1) + "\n")


if __name__ == "__main__":
    main()
