"""Benchmarks of paper 001 §IV-C: the 3D-SLIP baseline against the time-varying LIPM.

Rows (ratio = baseline median / our median, both measured here, in this process):

* ``T_r solve (eqs. 9-11)`` against ``SLIP periodic gait (optimise + integrate)``: the claim of the
  paper (24.9 s against 8 ms, about 3000x).
* ``TV-LIPM half cycle (T_r + closed form)`` against the same SLIP search: what it costs to *have* the
  trajectory in each model.
* ``TV-LIPM closed-form half cycle`` against ``SLIP half-cycle integration`` (one solve_ivp run with
  events, no search): the per-trajectory cost without any optimisation.
"""

from __future__ import annotations

import numpy as np

from gaitshift.analysis.slip_compare import tvlip_half_cycle
from gaitshift.bench import Result, benchmark, timed
from gaitshift.models.slip import SlipParams, periodic_half_cycle, simulate_half_cycle
from gaitshift.models.stiffness import solve_running

SPEED = 3.5


@benchmark("slip")
def bench_slip(quick: bool) -> list[Result]:
    p = SlipParams()
    g = p.gravity
    gait = periodic_half_cycle(SPEED, params=p)
    hc = gait.half_cycle
    h, tss, tf = float(hc.touchdown[2]), hc.stance_duration, hc.flight_duration
    T_r = float(solve_running(h, tss, tf, g)[0])
    t = np.linspace(0.0, hc.t_end, 401)

    def slip_search() -> object:
        return periodic_half_cycle(SPEED, params=p)

    def slip_once() -> object:
        return simulate_half_cycle(p, hc.state0, hc.theta, hc.phi, dense=True)

    def tr_solve() -> object:
        return solve_running(h, tss, tf, g)

    def tv_curve() -> object:
        return tvlip_half_cycle(hc.state0[:3], hc.state0[3:], hc.foot, hc.t_touchdown, hc.t_liftoff, T_r, t, g)

    def tv_full() -> object:
        T = float(solve_running(h, tss, tf, g)[0])
        return tvlip_half_cycle(hc.state0[:3], hc.state0[3:], hc.foot, hc.t_touchdown, hc.t_liftoff, T, t, g)

    n_fast, n_slip = (5, 1) if quick else (300, 15)
    size = f"{SPEED} m/s half cycle"
    note = f"SLIP: {gait.iterations} LM iterations, {gait.integrations} integrations"
    return [
        timed(
            "T_r solve (eqs. 9-11)",
            size,
            tr_solve,
            n_fast,
            baseline=("SLIP optimise+integrate", slip_search, n_slip),
            paper="8 ms vs 24.9 s (3112x)",
            note=note,
        ),
        timed(
            "TV-LIPM half cycle (T_r + 401 samples)",
            size,
            tv_full,
            n_fast,
            baseline=("SLIP optimise+integrate", slip_search, n_slip),
            paper="-",
        ),
        timed(
            "TV-LIPM closed form (401 samples)",
            size,
            tv_curve,
            n_fast,
            baseline=("SLIP one integration", slip_once, max(n_slip, 3 if quick else 30)),
            paper="-",
            note="no search on either side",
        ),
    ]
