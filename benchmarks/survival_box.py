"""Survival inside the RL box of issue 28, from a finished (or partial) run of the survival spec.

The box: push <= 0.5 m/s of base velocity (every case of docs/campaigns/g1-survival.yaml), floor
friction >= 0.4, link masses and base CoM within the RL ranges (every case), latency <= 8 ms (every
case), ``typical`` noise; for walking (the plan walks only) and for running up to 1.5 m/s (the plan
runs, commanded speed <= 1.5 m/s). Prints the survival with its Wilson 95 % interval per group, and the
same outside the box (``rl-peer`` noise, friction < 0.4, faster runs).

With a second folder (the same spec after a change), the two runs side by side on the cases both
hold (paired: the same draws), with the cases each change rescued and the new falls, and the falls'
causes in each.

Run: python benchmarks/survival_box.py runs/g1-survival [runs/g1-survival-after]
"""

from __future__ import annotations

import math
import sys
from collections import Counter
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


def _cell(rs: list[dict[str, Any]]) -> str:
    k = sum(not r["fell"] for r in rs)
    lo, hi = wilson(k, len(rs))
    return f"{k} = {100 * k / max(1, len(rs)):.1f} % ({100 * lo:.1f}-{100 * hi:.1f})"


def single(rows: list[dict[str, Any]]) -> None:
    """One run's groups."""
    print(f"{len(rows)} rows")
    print("| group | cases | survived | survival | Wilson 95 % |")
    print("|---|---|---|---|---|")
    for name, rs in groups(rows).items():
        k = sum(not r["fell"] for r in rs)
        lo, hi = wilson(k, len(rs))
        print(f"| {name} | {len(rs)} | {k} | {100 * k / max(1, len(rs)):.1f} % | {100 * lo:.1f}-{100 * hi:.1f} % |")


def paired(before: list[dict[str, Any]], after: list[dict[str, Any]]) -> None:
    """Two runs of one spec on the cases both hold: groups side by side, rescued, new falls, causes."""
    b = {r["case_hash"]: r for r in before}
    a = {r["case_hash"]: r for r in after}
    common = sorted(set(a) & set(b))
    rows_b, rows_a = [b[h] for h in common], [a[h] for h in common]
    print(f"{len(common)} cases in both runs")
    print("| group | cases | before | after | rescued | new falls |")
    print("|---|---|---|---|---|---|")
    ga = groups(rows_a)
    for name, rs in groups(rows_b).items():
        hs = {r["case_hash"] for r in rs} & {r["case_hash"] for r in ga[name]}
        rescued = sum(bool(b[h]["fell"]) and not a[h]["fell"] for h in hs)
        new = sum(not b[h]["fell"] and bool(a[h]["fell"]) for h in hs)
        print(f"| {name} | {len(rs)} | {_cell(rs)} | {_cell(ga[name])} | {rescued} | {new} |")
    for label, rs in (("before", rows_b), ("after", rows_a)):
        causes = Counter(r["fall_cause"] for r in rs if r["fell"])
        print(f"causes {label}: " + ", ".join(f"{c} {n}" for c, n in causes.most_common()))


def main(folder: str, after: str | None = None) -> None:
    rows = Store(folder).table().to_pylist()
    if after is None:
        single(rows)
    else:
        paired(rows, Store(after).table().to_pylist())


if __name__ == "__main__":
    main(*(sys.argv[1:3] if len(sys.argv) > 1 else ["runs/g1-survival"]))
