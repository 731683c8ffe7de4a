"""The fixed horizons of a VHIP run (paper 003): eq. (13) prepared once for every kind of segment.

All running steps share one vertical CoM profile, hence one tridiagonal matrix: it is factorised once
(:class:`~gaitshift.models.tridiagonal.Horizon`) and each step costs one back-substitution. The same
holds for the start (standing double support + first stance, State Switching 1) and the stop (flight,
last stance, final double support, State Switching 3), whose segmented ZMP problems get prepared
solvers (:class:`~gaitshift.planners.vhip.switching.SwitchingSolver`).

The unit responses U (to the start velocity) and V (to the end velocity) of the running step give the
lateral oscillation in closed form: after a left stance the CoM leaves with ``-u`` (to the right) and
the footholds are exactly ``step_width`` apart when ``u = w / (U_n - V_n + U_0 - V_0)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from gaitshift.models.arrays import FloatArray
from gaitshift.models.tridiagonal import Horizon
from gaitshift.models.vhip import VerticalGait, row_weights, stance_profiles
from gaitshift.planners.vhip.switching import SwitchingSolver
from gaitshift.scenario.vhip import VhipScenario
from gaitshift.trajectory.contract import LEFT

__all__ = ["VhipHorizons"]

#: (z, zd, zdd) of a horizon, each (n+1,): m, m/s, m/s^2
Vertical = tuple[FloatArray, FloatArray, FloatArray]


@dataclass(frozen=True, eq=False)
class VhipHorizons:
    """Everything about a VHIP run that does not depend on the commands.

    Attributes:
        dt, g: sample step (s) and gravity (m/s^2).
        n_step, n_sup, n_fly: samples per running step, its stance and its flight.
        n_start, n_stop: samples of the start and stop double supports.
        vertical: the vertical gait (stance sextics and flight parabola, eqs. (3)-(6)).
        run_z, run_w, run_horizon: vertical profile, row weights of eq. (9') and factorised eq. (13)
            of a running step (take-off to take-off, n_step + 1 samples).
        U, V: responses (n_step + 1,) of the running step to a unit start / end velocity.
        width: step width, m; u_left: lateral take-off velocity after a left stance, m/s (sign: see
            :meth:`oscillation`).
        start_z, start_w, start_solver: the start horizon (n_start + n_sup + 1 samples) and its solver.
        stop_z, stop_w, stop_solver: the stop horizon (n_fly + n_sup + n_stop + 1 samples) and its
            solver (prepared on the reversed weights: a stop is a start in reversed time).
        zmp_half: half sole size minus the ZMP margin (2,), m.
    """

    dt: float
    g: float
    n_step: int
    n_sup: int
    n_fly: int
    n_start: int
    n_stop: int
    vertical: VerticalGait
    run_z: Vertical
    run_w: FloatArray
    run_horizon: Horizon
    U: FloatArray
    V: FloatArray
    width: float
    u_left: float
    start_z: Vertical
    start_w: FloatArray
    start_solver: SwitchingSolver
    stop_z: Vertical
    stop_w: FloatArray
    stop_solver: SwitchingSolver
    zmp_half: FloatArray

    @classmethod
    def from_scenario(cls, sc: VhipScenario) -> VhipHorizons:
        """Prepare the horizons of ``sc`` (one factorisation per horizon)."""
        dt, g = float(sc.dt), float(sc.gravity)
        n_step = round(sc.step_period / dt)
        n_sup = round(sc.step_period * sc.stance_ratio / dt)
        n_fly = n_step - n_sup
        n_start = round(sc.start_double_support / dt)
        n_stop = round(sc.stop_double_support / dt)
        vg = stance_profiles(sc.heights, g, n_sup * dt, n_fly * dt)
        # cyclic running step (take-off to take-off): one factorisation for the whole run
        run_z = vg.running_step(dt, n_fly, n_sup)
        run_w = row_weights(run_z[0], run_z[2], g, dt)
        run_h = Horizon(run_w, dt)
        zero = np.zeros(n_step + 1)
        U = run_h.solve(zero, 1.0, 0.0)  # response to the start velocity
        V = run_h.solve(zero, 0.0, 1.0)  # response to the end velocity
        width = float(sc.step_width)
        start_z = vg.start_horizon(dt, n_start, n_sup)
        start_w = row_weights(start_z[0], start_z[2], g, dt)
        start_h = Horizon(start_w, dt)
        stop_z = vg.stop_horizon(dt, n_fly, n_sup, n_stop)
        stop_w = row_weights(stop_z[0], stop_z[2], g, dt)
        L, W = sc.foot.size
        return cls(
            dt=dt,
            g=g,
            n_step=n_step,
            n_sup=n_sup,
            n_fly=n_fly,
            n_start=n_start,
            n_stop=n_stop,
            vertical=vg,
            run_z=run_z,
            run_w=run_w,
            run_horizon=run_h,
            U=U,
            V=V,
            width=width,
            u_left=width / (U[-1] - V[-1] + U[0] - V[0]),
            start_z=start_z,
            start_w=start_w,
            start_solver=SwitchingSolver(start_w, n_start, dt, start_h),
            stop_z=stop_z,
            stop_w=stop_w,
            stop_solver=SwitchingSolver(stop_w[::-1].copy(), n_stop, dt),
            zmp_half=np.array([0.5 * L - sc.foot.zmp_margin, 0.5 * W - sc.foot.zmp_margin]),
        )

    def oscillation(self, side: int) -> float:
        """Lateral take-off velocity of the periodic oscillation after a stance on ``side``, m/s."""
        return self.u_left if side == LEFT else -self.u_left
