"""The block-field table of docs/perception.md: the G1 walking ``docs/perception/g1-blocks-walk.yaml``
on four fields of random blocks (the field's ``seed`` 0-3), seeds 0-2, with footholds judged in the plane
(``footholds: plane``), on the profile alone (``footholds: profile``) and blind; a campaign on the
campaign engine (Dask, one worker process per core given).

    PYTHONPATH=src .venv/bin/python benchmarks/perception_blocks.py [--out out/g1-blocks] [--workers 2] \
        [--fields 4] [--json benchmarks/perception_blocks.json] [--scenario docs/perception/g1-blocks-walk.yaml]

The field variants are written into ``--out`` as scenarios (the field's seed and the ``sim:`` block
changed, nothing else) and run as the campaign's scenario axis; the cases already in ``--out`` are not
run again. The table: per variant and field, whether it fell (when, why), the steps, the map's error
under the feet (median, p95), the true soles' distance from the nearest step edge (min, median).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import Any

import yaml

ROOT = Path(__file__).resolve().parents[1]
SCENARIO = ROOT / "docs" / "perception" / "g1-blocks-walk.yaml"
#: the variants: the ``sim:`` block each field is run with
VARIANTS = {
    "plane": {"terrain": "perceived", "footholds": "plane"},
    "profile": {"terrain": "perceived", "footholds": "profile"},
    "blind": {"terrain": "blind"},
}
sys.path.insert(0, str(Path(__file__).parent))
from perception_crossings import crossing, table  # noqa: E402


def fields(scenario: Path, out: Path, count: int) -> list[str]:
    """Write the variants of ``scenario`` on fields 0..``count``-1 into ``out``; their paths."""
    base = yaml.safe_load(scenario.read_text())
    out.mkdir(parents=True, exist_ok=True)
    paths = []
    for name, sim in VARIANTS.items():
        for f in range(count):
            sc = json.loads(json.dumps(base))
            for piece in sc["terrain"]:
                if "blocks" in piece:
                    piece["blocks"]["seed"] = f
            sc["sim"] = sim
            path = out / f"{scenario.stem}-{name}-field{f}.yaml"
            path.write_text(yaml.safe_dump(sc, sort_keys=False))
            paths.append(str(path))
    return paths


def main() -> None:
    from gaitshift.campaign.run import run_campaign
    from gaitshift.campaign.spec import load_spec
    from gaitshift.campaign.store import Store

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", type=Path, default=SCENARIO)
    ap.add_argument("--fields", type=int, default=4)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", type=Path, default=ROOT / "out" / "g1-blocks")
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args()
    data: dict[str, Any] = {
        "name": "g1-blocks",
        "description": "G1 over fields of random blocks: footholds in the plane, on the profile, blind",
        "task": "simulate",
        "axes": {"scenario": fields(args.scenario, args.out / "scenarios", args.fields), "seed": [0, 1, 2]},
    }
    text = yaml.safe_dump(data, sort_keys=False)
    t0 = time.perf_counter()
    summary = run_campaign(load_spec(data | {"base": str(ROOT)}), text, args.out / "campaign", workers=args.workers)
    rows = [crossing(r) for r in Store(args.out / "campaign").table().to_pylist()]
    for r in rows:  # the variant in the terrain column (the scenario's sim: block set it)
        r["terrain"] = next(v for v in VARIANTS if f"-{v}-" in r["scenario"])
    rows.sort(key=lambda r: (list(VARIANTS).index(r["terrain"]), r["scenario"], r["seed"]))
    print(table(rows))
    crossed = {v: sum(1 for r in rows if r["terrain"] == v and r["fell"] is False) for v in VARIANTS}
    print(f"\ncrossed of {args.fields * 3} each: {crossed}")
    print(f"{len(rows)} runs ({summary.ran} now) in {time.perf_counter() - t0:.0f} s with {args.workers} workers")
    if args.json is not None:
        args.json.write_text(json.dumps(rows, indent=1) + "\n")


if __name__ == "__main__":
    main()
