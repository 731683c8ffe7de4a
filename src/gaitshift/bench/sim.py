"""Closed-loop speed: one control tick (state read + whole-body QP + physics step) of the G1.

The real-time factor is the control period divided by the median tick time (>= 0.5 required by
issue 5). Baseline: the bare physics step ``mj_step`` of the same model (what the QP adds on top).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from gaitshift.bench import Result, benchmark, timed


def _tick_fns() -> tuple[Callable[[], None], Callable[[], None], Callable[[], None], float]:
    import mujoco
    import numpy as np

    from gaitshift.control.wbc import TickReference, WholeBodyController
    from gaitshift.sim.plant import build_plant, standing_qpos

    plant = build_plant(0.002)
    m = plant.model
    d = mujoco.MjData(m)
    q0 = standing_qpos(plant)
    d.qpos[:] = q0
    mujoco.mj_forward(m, d)
    ctrl = WholeBodyController(plant, q0)
    feet = np.array([plant.sole_frame(d, s)[0] for s in (0, 1)])
    com = d.subtree_com[0].copy()
    ref = TickReference.still(com, feet)
    ref_ss = TickReference.still(com, feet + np.array([[0, 0, 0], [0, 0, 0.02]]), stance=(True, False))
    d2 = mujoco.MjData(m)
    d2.qpos[:] = q0

    def tick(r: Any) -> Callable[[], None]:
        def f() -> None:
            mujoco.mj_forward(m, d)
            mujoco.mj_subtreeVel(m, d)
            tau, _ = ctrl.compute(d, r)
            d.ctrl[:] = tau
            mujoco.mj_step(m, d)

        return f

    def physics() -> None:
        mujoco.mj_step(m, d2)

    return tick(ref), tick(ref_ss), physics, plant.dt


@benchmark("sim")
def bench_sim(quick: bool) -> list[Result]:
    ds, ss, physics, dt = _tick_fns()
    n = 20 if quick else 1000
    out = []
    for name, fn in (("double support", ds), ("single support", ss)):
        r = timed("G1 control tick (QP + mj_step)", name, fn, n, baseline=("mj_step only", physics, n), paper="-")
        out.append(Result(**{**r.__dict__, "note": f"real-time factor {dt / r.median_s:.2f} at {dt * 1e3:.0f} ms"}))
    return out
