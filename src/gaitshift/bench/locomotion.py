"""Benchmarks of the online locomotion generator (issue 11: planning per step p99 <= 1 ms, one
sample emitted per control tick <= 20 us median), with the paper-003 VHIP generator as the baseline
in the same run."""

from __future__ import annotations

import time

import numpy as np

from gaitshift.bench import Result, benchmark, timed
from gaitshift.planners.locomotion.generator import LocomotionGenerator
from gaitshift.planners.locomotion.params import params_from_scenario
from gaitshift.planners.online.generator import OnlineGenerator
from gaitshift.scenario.facts import RobotFacts
from gaitshift.scenario.loader import load_scenario

#: the G1's facts as its model gives them (gaitshift robots), so that the bench loads no model
G1 = RobotFacts("g1", 33.34, 0.6333, 0.6922, (0.18, 0.07), 0.237)


def _generators(dt: float, vx: float, yaw_rate: float) -> tuple[LocomotionGenerator, OnlineGenerator]:
    sc = load_scenario({"planner": "locomotion", "dt": dt})
    gen = LocomotionGenerator(params_from_scenario(sc, G1))
    gen.command(vx, 0.0, yaw_rate)
    for _ in range(12):
        gen.step()
    vh = OnlineGenerator(load_scenario("paper003-variable-speed").model_copy(update={"dt": dt}))
    vh.command(0.9, 0.1)
    for _ in range(8):
        vh.step()
    return gen, vh


def _planning_row(gen: LocomotionGenerator, vh: OnlineGenerator, reps: int, label: str) -> Result:
    """Planning alone (:meth:`LocomotionGenerator.plan_due` at each step start; the samples are then
    emitted untimed), against the VHIP generator's whole online step in the same run."""
    times = np.empty(reps)
    for k in range(reps):
        t0 = time.perf_counter()
        gen.plan_due()
        times[k] = time.perf_counter() - t0
        gen.step()
    base = timed("", "", vh.step, reps)
    return Result(
        f"locomotion: plan one {label} step (horizon, footholds, samples)",
        f"dt={gen.dt * 1e3:g} ms",
        float(np.median(times)),
        float(np.percentile(times, 99)),
        reps,
        "VHIP online step (paper 003)",
        base.median_s,
        None,
        "goal p99 <= 1 ms",
        base.p99_s,
    )


@benchmark("locomotion")
def bench_locomotion(quick: bool) -> list[Result]:
    reps = 20 if quick else 1000
    out = []
    for dt in (0.002, 0.001):
        for gait, vx, w in (("walk", 0.6, 0.3), ("run", 1.5, -0.3)):
            gen, vh = _generators(dt, vx, w)
            out.append(_planning_row(gen, vh, reps, f"{gait} (turning {w:+g} rad/s)"))
            out.append(
                timed(
                    f"locomotion: one control tick ({gait})",
                    f"dt={dt * 1e3:g} ms",
                    gen.tick,
                    reps * 20,
                    baseline=("VHIP tick", vh.tick, reps * 20),
                    note="goal <= 20 us median; includes planning ticks",
                )
            )
    return out
