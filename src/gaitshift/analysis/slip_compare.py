"""Fig. 9 of paper 001: the time-varying LIPM against a periodic 3D-SLIP half cycle.

Alignment (TOF to TOF: half flight, stance, half flight). The SLIP half cycle of
:func:`gaitshift.models.slip.periodic_half_cycle` gives the event times t_td (touchdown), t_lo
(lift-off), t_end (next TOF), the foot point f and the TOF state (p0, v0). The TV-LIPM half cycle uses

* the same TOF state (p0, v0) at t = 0 (so the first flight is the same parabola in both models);
* ballistic flight for ``t_td`` (eqs. (5)-(6));
* one support phase of duration ``tau_SS = t_lo - t_td`` with the ZMP fixed at the foot point,
  ``c_k = c_{k+1} = f`` (f_z = 0), and the constant stiffness T_r (eqs. (3)-(4));
* ballistic flight for ``t_end - t_lo``;
* T_r from :func:`gaitshift.models.stiffness.solve_running` with h = the CoM height at touchdown of the SLIP,
  tau_SS as above and ``tau_F = t_td + (t_end - t_lo)`` (the flight time per step).

The vertical TV-LIPM is then periodic by construction: its touchdown height is h and its touchdown
velocity -g t_td equals v_r = -g tau_F / 2 when the two flight halves are equal (they are for the
time-symmetric periodic SLIP gait). The horizontal motion is propagated open loop from the same
state and the same foot, so its deviation measures how well the constant stiffness 1/T_r^2 stands in
for the SLIP's time-varying ``(k/m)(l0/L - 1)``.

Timing: both computations in the same process. The SLIP side is the gait optimisation plus its final
dense integration (what it takes to *have* the SLIP trajectory); the TV-LIPM side is the T_r solve
(paper 001: 24.9 s against 8 ms). The closed-form evaluation of the TV-LIPM samples is timed too.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from gaitshift.errors import InfeasibleError
from gaitshift.models.slip import PeriodicGait, SlipParams, periodic_half_cycle
from gaitshift.models.stiffness import solve_running
from gaitshift.models.tvlip import flight_state, support_state

#: Paper 001 §IV-C figures.
PAPER_SLIP_S = 24.9
PAPER_TVLIP_S = 8e-3


def tvlip_half_cycle(
    p0: np.ndarray,
    v0: np.ndarray,
    foot: np.ndarray,
    t_touchdown: float,
    t_liftoff: float,
    T: float,
    t: np.ndarray,
    g: float = 9.81,
) -> tuple[np.ndarray, np.ndarray]:
    """TV-LIPM CoM over a TOF-to-TOF half cycle aligned to a SLIP half cycle.

    Args:
        p0, v0: CoM state at the first TOF, shape (3,).
        foot: foot point = ZMP during stance, shape (3,).
        t_touchdown, t_liftoff: phase boundaries, s.
        T: support stiffness (T_r), s.
        t: sample times, shape (n,), s (samples beyond t_liftoff continue the ballistic flight).
        g: gravity, m/s^2.

    Returns:
        (p, v), each shape (n, 3): eqs. (5)-(6) before t_touchdown, (3)-(4) with c_k = c_{k+1} = foot
        in stance, (5)-(6) after lift-off.
    """
    p0, v0, foot = (np.asarray(a, float) for a in (p0, v0, foot))
    t = np.asarray(t, float)
    tau = t_liftoff - t_touchdown
    p_td, v_td, _ = flight_state(p0, v0, t_touchdown, g)
    p_lo, v_lo, _, _ = support_state(p_td, v_td, foot, foot, T, tau, tau, g)
    f1, s, f2 = t < t_touchdown, (t >= t_touchdown) & (t < t_liftoff), t >= t_liftoff
    p = np.empty((t.size, 3))
    v = np.empty((t.size, 3))
    p[f1], v[f1], _ = flight_state(p0, v0, t[f1], g)
    p[s], v[s], _, _ = support_state(p_td, v_td, foot, foot, np.full(s.sum(), T), tau, t[s] - t_touchdown, g)
    p[f2], v[f2], _ = flight_state(p_lo, v_lo, t[f2] - t_liftoff, g)
    return p, v


@dataclass(frozen=True)
class SlipComparison:
    """Numbers and samples of the Fig. 9 comparison (SI units).

    Attributes:
        gait: the periodic SLIP half cycle.
        t: sample times (n,), s, from TOF (0) to the next TOF.
        slip_pos, tvlip_pos: CoM positions (n, 3), m.
        T_r, v_r: TV-LIPM running stiffness, s, and touchdown vertical velocity, m/s.
        height, stance, flight: h, tau_SS, tau_F fed to the T_r solve.
        max_deviation: max over t of |slip - tvlip| per axis (3,), m.
        displacement: SLIP displacement over the half cycle, |p(t_end) - p(0)| per axis (3,), m.
        excursion: SLIP peak-to-peak range per axis (3,), m.
        slip_time_s: median wall time of SLIP optimisation + integration, s.
        tvlip_time_s: median wall time of the T_r solve, s.
        tvlip_eval_s: median wall time of the closed-form sampling of the TV-LIPM half cycle, s.
        tvlip_end_defect: TV-LIPM state at its end minus the mirrored start (z, vx, vy, vz) (4,).
        tr_iterations: Newton iterations of the T_r solve.
    """

    gait: PeriodicGait
    t: np.ndarray
    slip_pos: np.ndarray
    tvlip_pos: np.ndarray
    T_r: float
    v_r: float
    height: float
    stance: float
    flight: float
    max_deviation: np.ndarray
    displacement: np.ndarray
    excursion: np.ndarray
    slip_time_s: float
    tvlip_time_s: float
    tvlip_eval_s: float
    tvlip_end_defect: np.ndarray
    tr_iterations: int
    slip_repeats: int
    tvlip_repeats: int

    @property
    def ratio(self) -> float:
        """SLIP time over T_r time (paper: 24.9 s / 8 ms = 3112)."""
        return self.slip_time_s / self.tvlip_time_s

    def as_dict(self) -> dict[str, Any]:
        hc, p = self.gait.half_cycle, self.gait.params
        axes = ("x", "y", "z")
        return {
            "slip": {
                "mass_kg": p.mass,
                "stiffness_N_per_m": p.stiffness,
                "leg_length_m": p.leg_length,
                "relative_stiffness": p.relative_stiffness,
                "gravity": p.gravity,
                "speed_m_per_s": self.gait.speed,
                "step_width_m": self.gait.step_width,
                "tof_height_m": float(hc.state0[2]),
                "tof_lateral_velocity_m_per_s": float(hc.state0[4]),
                "theta_rad": hc.theta,
                "phi_rad": hc.phi,
                "touchdown_height_m": float(hc.touchdown[2]),
                "stance_s": hc.stance_duration,
                "flight_s": hc.flight_duration,
                "flight_before_s": hc.flight_before,
                "flight_after_s": hc.flight_after,
                "half_cycle_s": hc.t_end,
                "foot_m": hc.foot.tolist(),
                "periodicity_error": float(np.max(np.abs(hc.mirror_error()))),
                "optimiser_iterations": self.gait.iterations,
                "half_cycle_integrations": self.gait.integrations,
            },
            "tvlip": {
                "T_r_s": self.T_r,
                "v_r_m_per_s": self.v_r,
                "h_m": self.height,
                "tau_SS_s": self.stance,
                "tau_F_s": self.flight,
                "newton_iterations": self.tr_iterations,
                "end_defect_z_vx_vy_vz": self.tvlip_end_defect.tolist(),
            },
            "max_deviation_m": dict(zip(axes, self.max_deviation.tolist(), strict=True)),
            "displacement_m": dict(zip(axes, self.displacement.tolist(), strict=True)),
            "excursion_m": dict(zip(axes, self.excursion.tolist(), strict=True)),
            "deviation_over_x_displacement": dict(
                zip(axes, (self.max_deviation / self.displacement[0]).tolist(), strict=True)
            ),
            "timing": {
                "slip_optimise_and_integrate_s": self.slip_time_s,
                "slip_repeats": self.slip_repeats,
                "tvlip_T_r_solve_s": self.tvlip_time_s,
                "tvlip_repeats": self.tvlip_repeats,
                "tvlip_closed_form_samples_s": self.tvlip_eval_s,
                "ratio": self.ratio,
                "paper_slip_s": PAPER_SLIP_S,
                "paper_tvlip_s": PAPER_TVLIP_S,
                "paper_ratio": PAPER_SLIP_S / PAPER_TVLIP_S,
            },
        }


def _median_time(fn: Callable[[], Any], repeats: int) -> tuple[float, Any]:
    out = fn()  # warm-up (imports, caches)
    times = np.empty(repeats)
    for i in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times[i] = time.perf_counter() - t0
    return float(np.median(times)), out


def compare(
    speed: float = 3.5,
    *,
    flight: float = 0.2,
    step_width: float = 0.1,
    params: SlipParams | None = None,
    samples: int = 401,
    slip_repeats: int = 3,
    tvlip_repeats: int = 200,
) -> SlipComparison:
    """Optimise the periodic SLIP half cycle, feed its timings to the TV-LIPM and compare (Fig. 9).

    Args:
        speed: forward TOF speed, m/s. flight: SLIP flight time per step, s. step_width: foot to
        mid-line, m. params: SLIP parameters. samples: number of time samples.
        slip_repeats, tvlip_repeats: timing repetitions (median reported; >= 1).

    Raises:
        InputError: bad arguments. InfeasibleError: no periodic SLIP gait or no T_r root.
    """
    p = params or SlipParams()
    g = p.gravity
    slip_s, gait = _median_time(
        lambda: periodic_half_cycle(speed, flight=flight, step_width=step_width, params=p), max(1, slip_repeats)
    )
    hc = gait.half_cycle
    h = float(hc.touchdown[2])
    tss = hc.stance_duration
    tf = hc.flight_duration
    tr_s, (T_r, v_r, res, it) = _median_time(lambda: solve_running(h, tss, tf, g), max(1, tvlip_repeats))
    T_r, v_r = float(T_r), float(v_r)
    if not (float(res) < 1e-10 and T_r > 0):
        raise InfeasibleError(f"no running stiffness for h={h}, tau_SS={tss}, tau_F={tf}")

    t = np.linspace(0.0, hc.t_end, samples)
    t = np.union1d(t, [hc.t_touchdown, hc.t_liftoff])
    slip_pos = hc.sample(t)[:, :3]

    def tv() -> tuple[np.ndarray, np.ndarray]:
        return tvlip_half_cycle(hc.state0[:3], hc.state0[3:], hc.foot, hc.t_touchdown, hc.t_liftoff, T_r, t, g)

    eval_s, (tv_pos, tv_vel) = _median_time(tv, max(1, tvlip_repeats // 4))
    dev = np.max(np.abs(slip_pos - tv_pos), axis=0)
    s0 = hc.state0
    end = np.concatenate([tv_pos[-1], tv_vel[-1]])
    defect = np.array([end[2] - s0[2], end[3] - s0[3], end[4] + s0[4], end[5]])
    return SlipComparison(
        gait=gait,
        t=t,
        slip_pos=slip_pos,
        tvlip_pos=tv_pos,
        T_r=T_r,
        v_r=v_r,
        height=h,
        stance=tss,
        flight=tf,
        max_deviation=dev,
        displacement=np.abs(slip_pos[-1] - slip_pos[0]),
        excursion=np.ptp(slip_pos, axis=0),
        slip_time_s=slip_s,
        tvlip_time_s=tr_s,
        tvlip_eval_s=eval_s,
        tvlip_end_defect=defect,
        tr_iterations=int(it),
        slip_repeats=max(1, slip_repeats),
        tvlip_repeats=max(1, tvlip_repeats),
    )
