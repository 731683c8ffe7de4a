"""Benchmarks of the online locomotion generator (issue 11: planning per step p99 <= 1 ms, one
sample emitted per control tick <= 20 us median), with the paper-003 VHIP generator as the baseline
in the same run."""

from __future__ import annotations

import time

import numpy as np

from gaitshift.bench import Result, benchmark, timed
from gaitshift.planners.locomotion.generator import LocomotionGenerator
from gaitshift.planners.locomotion.params import params_from_scenario
from gaitshift.planners.vhip.generator import VhipGenerator
from gaitshift.scenario.facts import RobotFacts
from gaitshift.scenario.loader import load_scenario

#: the G1's facts as its model gives them (gaitshift robots), so that the bench loads no model
G1 = RobotFacts("g1", 33.34, 0.6333, 0.6922, (0.18, 0.07), 0.237)


def _generators(dt: float, vx: float, yaw_rate: float) -> tuple[LocomotionGenerator, VhipGenerator]:
    sc = load_scenario({"planner": "locomotion", "dt": dt})
    gen = LocomotionGenerator(params_from_scenario(sc, G1))
    gen.command(vx, 0.0, yaw_rate)
    for _ in range(12):
        gen.step()
    vh = VhipGenerator(load_scenario("paper003-variable-speed").model_copy(update={"dt": dt}))
    vh.command(0.9, 0.1)
    for _ in range(8):
        vh.step()
    return gen, vh


def _row(operation: str, dt: float, times: np.ndarray, baseline: str, base: Result, note: str) -> Result:
    return Result(
        operation,
        f"dt={dt * 1e3:g} ms",
        float(np.median(times)),
        float(np.percentile(times, 99)),
        len(times),
        baseline,
        base.median_s,
        None,
        note,
        base.p99_s,
    )


def _planning_row(gen: LocomotionGenerator, vh: VhipGenerator, reps: int, label: str) -> Result:
    """Planning alone (:meth:`LocomotionGenerator.plan_due` at each step start: the horizon solve, the
    footholds, the swings and the step's end state; its rows are written lazily by the ticks that
    emit them), against the VHIP generator's whole online step in the same run."""
    times = np.empty(reps)
    for k in range(reps):
        t0 = time.perf_counter()
        gen.plan_due()
        times[k] = time.perf_counter() - t0
        gen.step()
    base = timed("", "", vh.step, reps)
    op = f"locomotion: plan one {label} step (horizon, footholds, end state)"
    return _row(op, gen.dt, times, "VHIP online step (paper 003)", base, "goal p99 <= 1 ms")


def _whole_step_row(gen: LocomotionGenerator, reps: int, label: str) -> Result:
    """Everything one step costs, planning and the sampling of all its rows, emitted tick by tick
    (the planning row plus the step's ticks), against the same steps emitted in one block each
    (:meth:`LocomotionGenerator.step` on a fork of the generator, so the same commands and state)."""
    block = gen.fork()
    times = np.empty(reps)
    for k in range(reps):
        t0 = time.perf_counter()
        gen.plan_due()
        end = gen.next_plan_index
        for _ in range(max(1, (end if end is not None else gen.tick_index + 1) - gen.tick_index)):
            gen.tick()
        times[k] = time.perf_counter() - t0
    base = timed("", "", block.step, reps)
    op = f"locomotion: plan and emit one {label} step, tick by tick (all its samples)"
    return _row(op, gen.dt, times, "the same step emitted in one block", base, "total cost per step, for scale")


@benchmark("locomotion")
def bench_locomotion(quick: bool) -> list[Result]:
    reps = 20 if quick else 1000
    out = []
    for dt in (0.002, 0.001):
        for gait, vx, w in (("walk", 0.6, 0.3), ("run", 1.5, -0.3)):
            gen, vh = _generators(dt, vx, w)
            label = f"{gait} (turning {w:+g} rad/s)"
            out.append(_planning_row(gen, vh, reps, label))
            out.append(
                timed(
                    f"locomotion: one control tick ({gait})",
                    f"dt={dt * 1e3:g} ms",
                    gen.tick,
                    reps * 20,
                    baseline=("VHIP tick", vh.tick, reps * 20),
                    note="goal <= 20 us median; includes the planning ticks and the lazy sampling",
                )
            )
            out.append(_whole_step_row(gen, max(reps // 5, 5), label))
    return out
