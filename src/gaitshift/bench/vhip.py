"""Benchmarks of the online VHIP generator (paper 003).

* ``vhip.horizontal``: eq. (13) for one running step and for a whole 16 s run: our Thomas loop
  (baseline) vs scipy ``solve_banded``, LAPACK ``gtsv`` (the default) and the prefactorised
  ``gttrs`` the generator uses.
* ``vhip.foothold``: one Algorithm 1 computation (paper: < 1 ms; goal <= 0.1 ms).
* ``vhip.switching``: the start and stop NLP, our solver vs IPOPT in the same run (paper: < 4 ms
  with IPOPT; goal <= 1 ms with ours), at the paper's 4 ms and at our 1 ms sample step.
* ``vhip.online``: one online step (planning + emitting 0.4 s of samples) and one control tick
  (goal: p99 <= 1 ms, 4x under the paper's 4 ms control period).
"""

from __future__ import annotations

import numpy as np

from gaitshift.bench import Result, benchmark, timed
from gaitshift.models.tridiagonal import (
    Horizon,
    solve_banded_tridiagonal,
    solve_tridiagonal,
    thomas,
    tridiagonal_system,
)
from gaitshift.planners.vhip.foothold import target_foothold
from gaitshift.planners.vhip.generator import VhipGenerator
from gaitshift.planners.vhip.switching import SwitchingProblem, SwitchingSolver, stop_problem
from gaitshift.planners.vhip.switching_ipopt import solve_switching_ipopt
from gaitshift.scenario import load_scenario
from gaitshift.scenario.vhip import VhipScenario

SCENARIO = "paper003-variable-speed"


def _generator(dt: float | None = None) -> VhipGenerator:
    sc: VhipScenario = load_scenario(SCENARIO)
    if dt is not None:
        sc = sc.model_copy(update={"dt": dt})
    return VhipGenerator(sc)


def _solver_rows(label: str, w: np.ndarray, dt: float, reps: int, rhs: np.ndarray) -> list[Result]:
    """Three eq. (13) solvers on the weights ``w`` against our Thomas loop."""
    lo, di, up = tridiagonal_system(w)
    h = Horizon(w, dt)
    size = f"n={len(w)}"
    base = ("thomas (ours, Python)", lambda: thomas(lo, di, up, rhs), max(5, reps // (20 if len(w) > 1000 else 4)))
    return [
        timed(
            f"eq. (13) solve: LAPACK gtsv (default) [{label}]",
            size,
            lambda: solve_tridiagonal(lo, di, up, rhs),
            reps,
            baseline=base,
            paper="O(n) Thomas [27]",
        ),
        timed(
            f"eq. (13) solve: scipy solve_banded [{label}]",
            size,
            lambda: solve_banded_tridiagonal(lo, di, up, rhs),
            reps,
            baseline=base,
        ),
        timed(
            f"eq. (13) solve: prefactorised gttrs [{label}]",
            size,
            lambda: h.solve_rhs(rhs),
            reps,
            baseline=base,
            note="the generator factorises the running step once",
        ),
    ]


@benchmark("vhip.horizontal")
def bench_horizontal(quick: bool) -> list[Result]:
    gen = _generator()
    rng = np.random.default_rng(0)
    out = []
    reps = 20 if quick else 2000
    run_w = gen.horizons.run_w
    for label, w in (("one step", run_w), ("16 s run", np.tile(run_w[:-1], 40))):
        out += _solver_rows(label, w, gen.dt, reps, rng.normal(size=len(w)))
    return out


class _ThomasHorizon:
    """Eq. (13) solved from scratch by our Thomas loop at every call (the naive baseline)."""

    def __init__(self, w: np.ndarray, dt: float):
        self.w, self.dt = w, dt
        self.bands = tridiagonal_system(w)

    def solve_rhs(self, r: np.ndarray) -> np.ndarray:
        return thomas(*self.bands, r)


def _foothold_row(dt: float, reps: int) -> Result:
    """One Algorithm 1 computation at sample step ``dt`` against a Thomas solve per iteration."""
    gen = _generator(dt)
    c_prev, v_prev = np.array([0.0, 0.03]), np.array([0.6, -0.2])
    v_cmd, p_nom = np.array([0.9, 0.2]), np.array([0.3, -0.1])
    h = gen.horizons
    res = target_foothold(h.run_horizon, c_prev, v_prev, v_cmd, p_nom)
    naive = _ThomasHorizon(h.run_w, dt)
    return timed(
        "foothold (Algorithm 1, tol 1e-6)",
        f"dt={dt * 1e3:g} ms, n={gen.n_step + 1}",
        lambda: target_foothold(h.run_horizon, c_prev, v_prev, v_cmd, p_nom),
        reps,
        baseline=(
            "same loop, Thomas solve per iteration",
            lambda: target_foothold(naive, c_prev, v_prev, v_cmd, p_nom),
            max(5, reps // 50),
        ),
        paper="< 1 ms",
        note=f"{int(res.iterations.max())} iteration(s); goal <= 0.1 ms",
    )


@benchmark("vhip.foothold")
def bench_foothold(quick: bool) -> list[Result]:
    reps = 50 if quick else 5000
    return [_foothold_row(dt, reps) for dt in (0.004, 0.001)]


def _switching_problems(gen: VhipGenerator) -> tuple[SwitchingProblem, SwitchingProblem]:
    """A start to (0.3, u) m/s and a stop from (0, u) m/s on the horizons of ``gen``."""
    h, dt, width = gen.horizons, gen.dt, gen.width
    half = h.zmp_half
    start = SwitchingProblem(
        h.start_w,
        gen.n_start,
        dt,
        np.zeros(2),
        np.array([0.0, 0.5 * width]),
        np.zeros(2),
        np.array([0.3, gen.u_left]),
        np.array([-half[0], -0.5 * width - half[1]]),
        np.array([half[0], 0.5 * width + half[1]]),
    )
    stop = stop_problem(
        h.stop_w,
        gen.n_stop,
        dt,
        np.array([0.0, gen.u_left]),
        np.array([0.0, -width]),
        np.array([-half[0], -width - half[1]]),
        np.array([half[0], half[1]]),
    )
    return start, stop


def _switching_row(
    name: str, prob: SwitchingProblem, solver: SwitchingSolver, size: str, reps: int, ip_reps: int
) -> Result:
    """Our solver of one start/stop problem against IPOPT on the same problem."""
    solve_switching_ipopt(prob)  # build the casadi solver outside the timing, like ours
    ours = solver.solve(prob)
    ref = solve_switching_ipopt(prob)
    return timed(
        f"{name} NLP (16) + smoothness: ours",
        size,
        lambda: solver.solve(prob),
        reps,
        baseline=("IPOPT (casadi)", lambda: solve_switching_ipopt(prob), ip_reps),
        paper="< 4 ms (IPOPT)",
        note=f"J ours {ours.J.sum():.6g} vs IPOPT {ref.J.sum():.6g}; goal <= 1 ms",
    )


@benchmark("vhip.switching")
def bench_switching(quick: bool) -> list[Result]:
    out = []
    reps = 10 if quick else 1000
    ip_reps = 3 if quick else 40
    for dt in (0.004,) if quick else (0.004, 0.001):  # the smoke run: the paper's step (IPOPT at 1 ms: ~12 s)
        gen = _generator(dt)
        start, stop = _switching_problems(gen)
        h = gen.horizons
        size = f"dt={dt * 1e3:g} ms, n_ds={gen.n_start}"
        out.append(_switching_row("start", start, h.start_solver, size, reps, ip_reps))
        out.append(_switching_row("stop", stop, h.stop_solver, size, reps, ip_reps))
    return out


@benchmark("vhip.online")
def bench_online(quick: bool) -> list[Result]:
    out = []
    reps = 20 if quick else 1000
    for dt in (0.004, 0.001):
        gen = _generator(dt)
        gen.command(0.9, 0.1)
        for _ in range(8):
            gen.step()
        out.append(
            timed(
                "one online step (plan + emit 0.4 s)",
                f"dt={dt * 1e3:g} ms, {gen.n_step} ticks",
                gen.step,
                reps,
                paper="4 ms control period",
                note="goal p99 <= 1 ms",
            )
        )
        out.append(
            timed(
                "one control tick",
                f"dt={dt * 1e3:g} ms",
                gen.tick,
                reps * 20,
                paper="4 ms control period",
                note="includes the planning tick",
            )
        )
    return out
