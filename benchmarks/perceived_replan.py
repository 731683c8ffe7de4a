"""The perceived driver's re-plan in the tick and off it (issue 29: the controller inside its period).

One perceived scenario, closed loop on the estimate, three ways, in the same run:

* ``inline, lead 0`` (the baseline: what ``gaitshift simulate`` does): the re-plan runs in the tick at
  each phase boundary;
* ``inline, lead L``: the same re-plans made ``L`` s before their boundary, still in the tick
  (deterministic; the plans a background worker must reproduce);
* ``process, lead L``: a spawned worker re-plans on a copy of the map handed over at ``L`` s before each
  boundary (``ControllerSettings.replan``, docs/perception.md "The re-plan off the tick").

For each: the controller's tick (``Controller.tick``: estimator, map update, re-plan or hand-over, QP),
wall time per tick, median, p99, p99.9 and max, and the ticks over the control period; the re-plans, and
for the worker the ticks each plan took to come (``lags``) against the ticks between its request and its
boundary (in time when lag <= lead / period); the run's outcome and end position.

The simulation is not paced to a wall clock: a tick's wall time is its compute. Run on a quiet machine.

Run: PYTHONPATH=src python benchmarks/perceived_replan.py [--scenario S] [--lead 0.1] [--seed 0] [--json F]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.sim.scenario_run import simulate_scenario

SCENARIO = Path(__file__).resolve().parents[1] / "docs" / "perception" / "g1-stairs-up-ahead.yaml"


class TickClock:
    """A hook that times the controller's own ``tick`` (wall time, µs) and keeps the controller."""

    def __init__(self) -> None:
        self.us: list[float] = []
        self.ctrl: Any = None

    def attach(self, ctrl: Any) -> None:
        self.ctrl, tick = ctrl, ctrl.tick

        def timed(frame: Any, age: int = 0) -> Any:
            t0 = time.perf_counter()
            out = tick(frame, age)
            self.us.append((time.perf_counter() - t0) * 1e6)
            return out

        ctrl.tick = timed

    def __call__(self, k: int, t: float, d: Any) -> None:
        """Nothing per tick: the timing is in ``tick``."""


def one(scenario: str, seed: int, replan: str, lead: float) -> dict[str, Any]:
    """One closed-loop run; its tick times, re-plans and outcome."""
    import yaml

    sc = yaml.safe_load(Path(scenario).read_text())
    sc.setdefault("sim", {})
    sc["sim"] |= {"terrain": "perceived", "replan_lead": lead}
    clock = TickClock()
    run = simulate_scenario(sc, seed=seed, replan=replan, hooks=[clock])
    us = np.array(clock.us)
    period_us = clock.ctrl.period * 1e6
    out: dict[str, Any] = {
        "replan": replan,
        "lead_s": lead,
        "ticks": len(us),
        "tick_us": {q: round(float(np.percentile(us, p)), 1) for q, p in (("p50", 50), ("p99", 99), ("p99.9", 99.9))}
        | {"max": round(float(us.max()), 1)},
        "ticks_over_period": int((us > period_us).sum()),
        "ticks_over_10ms": int((us > 1e4).sum()),
        "replans": int(run.result.meta["replans"]),
        "fell": bool(run.result.fell),
        "end_x": round(float(run.result.arrays["qpos"][-1, 0]), 4),
    }
    lags = getattr(clock.ctrl.replan, "lags", None)
    if lags is not None:
        budget = round(lead / clock.ctrl.period)
        out["lag_ticks"] = {"p50": float(np.median(lags)), "max": int(max(lags))} if lags else {}
        out["in_time"] = f"{sum(lag <= budget for lag in lags)} of {len(lags)} (lag <= {budget} ticks)"
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenario", default=str(SCENARIO))
    ap.add_argument("--lead", type=float, default=0.1)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--json", default=None)
    a = ap.parse_args()
    rows = [
        one(a.scenario, a.seed, "inline", 0.0),
        one(a.scenario, a.seed, "inline", a.lead),
        one(a.scenario, a.seed, "process", a.lead),
    ]
    for r in rows:
        print(json.dumps(r))
    if a.json:
        Path(a.json).write_text(json.dumps({"scenario": a.scenario, "seed": a.seed, "runs": rows}, indent=1) + "\n")


if __name__ == "__main__":
    main()
