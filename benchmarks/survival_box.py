"""Survival inside the RL box of issue 28, from a finished (or partial) run of the survival spec.

The box: push <= 0.5 m/s of base velocity (every case of docs/campaigns/g1-survival.yaml), floor
friction >= 0.4, link masses and base CoM within the RL ranges (every case), latency <= 8 ms (every
case), ``typical`` noise; for walking (the plan walks only) and for running up to 1.5 m/s (the plan
runs, commanded speed <= 1.5 m/s). Prints the survival with its Wilson 95 % interval per group, and the
same outside the box (``rl-peer`` noise, friction < 0.4, faster runs).

Run: python benchmarks/survival_box.py runs/g1-survival
"""

from __future__ import annotations

import math
import sys
from typing import Any

from gaitshift.campaign.store import Store

#: the RL box's edges that the spec's own ranges do not already enforce
MIN_FRICTION, MAX_RUN_SPEED, BOX_NOISE = 0.4, 1.5, "typical"


def wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """The Wilson score interval of k successes in n trials."""
    if n == 0:
        return (math.nan, math.nan)
    p = k / n
    mid = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return (mid - half, mid + half)


def groups(rows: list[dict[str, Any]]) -> dict[str, list[dict[str, Any]]]:
    """The box's groups and the cases outside it."""
    ran = [r for r in rows if r["error"] is None and r["fell"] is not None]
    box = [r for r in ran if r["friction"] >= MIN_FRICTION and r["noise"] == BOX_NOISE]
    walk = [r for r in box if r["plan_gaits"] == "walk"]
    run = [r for r in box if "run" in str(r["plan_gaits"]) and r["speed"] <= MAX_RUN_SPEED]
    return {
        "box: walking": walk,
        f"box: running <= {MAX_RUN_SPEED} m/s": run,
        "box: all": box,
        "rl-peer noise (friction >= 0.4)": [
            r for r in ran if r["friction"] >= MIN_FRICTION and r["noise"] == "rl-peer"
        ],
        f"friction < {MIN_FRICTION}": [r for r in ran if r["friction"] < MIN_FRICTION],
        f"running > {MAX_RUN_SPEED} m/s (box noise, friction)": [
            r for r in box if "run" in str(r["plan_gaits"]) and r["speed"] > MAX_RUN_SPEED
        ],
        "every case": ran,
    }


def main(folder: str) -> None:
    rows = Store(folder).table().to_pylist()
    print(f"{len(rows)} rows")
    print("| group | cases | survived | survival | Wilson 95 % |")
    print("|---|---|---|---|---|")
    for name, rs in groups(rows).items():
        k = sum(not r["fell"] for r in rs)
        lo, hi = wilson(k, len(rs))
        print(f"| {name} | {len(rs)} | {k} | {100 * k / max(1, len(rs)):.1f} % | {100 * lo:.1f}-{100 * hi:.1f} % |")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "runs/g1-survival")
