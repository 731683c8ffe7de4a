"""Parameters of the locomotion generator: plain numbers, resolved from a scenario and its robot."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from gaitshift.errors import InputError
from gaitshift.planners.locomotion.steps import Timing
from gaitshift.scenario.facts import RobotFacts

__all__ = ["Limits", "LocomotionParams", "params_from_scenario"]


@dataclass(frozen=True)
class Limits:
    """What the generator may command and where a foot may land.

    Attributes:
        max_speed: largest |vx| forward, |vx| backward, |vy|, m/s (heading frame).
        max_yaw_rate: largest |yaw rate|, rad/s.
        max_accel: largest change per step of vx, vy (m/s) and of the yaw rate (rad/s).
        max_stride: largest forward or backward foothold displacement per step, m.
        width: (min, max) lateral distance between consecutive footholds, m (heading frame).
        max_turn: largest foot yaw change per step, rad.
    """

    max_speed: tuple[float, float, float]
    max_yaw_rate: float
    max_accel: tuple[float, float, float]
    max_stride: float
    width: tuple[float, float]
    max_turn: float


@dataclass(frozen=True)
class LocomotionParams:
    """Everything the generator needs, SI units.

    Attributes:
        gravity: g, m/s^2.
        height: nominal CoM height h above the ground, m.
        timing: phase durations (:class:`~gaitshift.planners.locomotion.steps.Timing`), multiples of dt.
        dt: sample step, s.
        foot_size: sole (length, width), m.
        zmp_margin: margin kept between the ZMP and the sole edge in the start and stop, m.
        step_width: lateral distance between the feet centres in the steady gait, m.
        swing_height: swing-foot apex above the higher end, m.
        gait: "auto", "walk" or "run".
        walk_to_run: speed above which ``auto`` switches to running, m/s.
        run_to_walk: speed below which ``auto`` switches back to walking, m/s (< walk_to_run).
        limits: command and foothold limits.
        first_swing: 0 left, 1 right: the foot that swings first.
    """

    gravity: float
    height: float
    timing: Timing
    dt: float
    foot_size: tuple[float, float]
    zmp_margin: float
    step_width: float
    swing_height: float
    gait: str
    walk_to_run: float
    run_to_walk: float
    limits: Limits
    first_swing: int = 1


# ---------------------------------------------------------------------------- defaults
#: paper 001: CoM height (m) and phase durations (s) the defaults scale from. Walking: Table II
#: (SS 0.40 s, DS 0.15 s). Running: SS 0.30 s and flight 0.18 s, between Table I (0.20 / 0.20) and
#: Table II (0.40 / 0.15): the G1 holds running up to 2 m/s only with a stance of about 0.25 s
#: (speed x stance <= 0.5 m, docs/simulation.md "Top speed"), which is this value Froude-scaled.
PAPER_HEIGHT = 0.95
PAPER_TIMING = {"walk_single": 0.40, "double": 0.15, "run_single": 0.30, "flight": 0.18, "start": 0.8, "stop": 1.0}
PAPER_FOOT = (0.22, 0.12)
PAPER_STEP_WIDTH = 0.20
PAPER_SWING = 0.08
#: Froude numbers v^2 / (g l) of the default walk -> run and run -> walk switches (docs/locomotion.md):
#: below the constant-height walk's envelope, which the G1 holds to Fr = 0.12 (0.9 m/s) and not at 0.15
FROUDE_UP = 0.10
FROUDE_DOWN = 0.06
#: the least gap between two soles side by side, as a share of the sole width (default width limits)
SOLE_CLEARANCE = 0.05
#: Froude numbers of the default speed limits: forward, backward, lateral
FROUDE_SPEED = (1.0, 0.05, 0.03)
#: default per-step accelerations: vx and vy as fractions of sqrt(g l), and the yaw rate (rad/s)
ACCEL_SHARE = (0.1, 0.07)
YAW_ACCEL = 0.3
MAX_YAW_RATE = 1.0
MAX_TURN = 0.4
STRIDE_PER_LEG = 1.3


def _on_grid(value: float, dt: float, multiple: int = 1) -> float:
    """``value`` rounded to a multiple of ``multiple * dt`` (at least one)."""
    q = multiple * dt
    return max(1, round(value / q)) * q


def params_from_scenario(sc: Any, facts: RobotFacts | None) -> LocomotionParams:
    """Resolve a :class:`~gaitshift.scenario.locomotion.LocomotionScenario` into numbers: every key
    left out takes its default from ``facts`` (the scenario's robot) or from paper 001
    (docs/locomotion.md, "Defaults")."""
    g, dt = float(sc.gravity), float(sc.dt)
    h = sc.height or (facts.com_height if facts else PAPER_HEIGHT)
    leg = sc.leg_length or (facts.leg_length if facts else h)
    lam = h / PAPER_HEIGHT
    ts = math.sqrt(lam)  # Froude time scaling: tau' = tau sqrt(lambda)
    tm = sc.timing
    timing = Timing(
        **{
            k: _on_grid(getattr(tm, k) or PAPER_TIMING[k] * ts, dt, 2 if k in ("start", "stop") else 1)
            for k in PAPER_TIMING
        }
    )
    sgl = math.sqrt(g * leg)
    foot = tuple(sc.foot.size) if sc.foot.size else (facts.sole_size if facts else PAPER_FOOT)
    width = sc.step_width or (facts.foot_separation if facts else PAPER_STEP_WIDTH * lam)
    lim = sc.limits
    max_stride = lim.max_stride or STRIDE_PER_LEG * leg
    accel = lim.max_accel or (ACCEL_SHARE[0] * sgl, ACCEL_SHARE[1] * sgl, YAW_ACCEL)
    speed = lim.max_speed or _default_speeds(sgl, max_stride, timing, sc.gait, float(accel[0]))
    limits = Limits(
        max_speed=(float(speed[0]), float(speed[1]), float(speed[2])),
        max_yaw_rate=lim.max_yaw_rate or MAX_YAW_RATE,
        max_accel=(float(accel[0]), float(accel[1]), float(accel[2])),
        max_stride=max_stride,
        width=_width_limits(lim.width, foot, width),
        max_turn=lim.max_turn or MAX_TURN,
    )
    up = sc.switch.walk_to_run or math.sqrt(FROUDE_UP * g * leg)
    down = sc.switch.run_to_walk or min(math.sqrt(FROUDE_DOWN * g * leg), 0.8 * up)
    return LocomotionParams(
        gravity=g,
        height=h,
        timing=timing,
        dt=dt,
        foot_size=(float(foot[0]), float(foot[1])),
        zmp_margin=sc.foot.zmp_margin if sc.foot.zmp_margin is not None else 0.1 * min(foot),
        step_width=float(width),
        swing_height=sc.swing_height if sc.swing_height is not None else PAPER_SWING * lam,
        gait=sc.gait,
        walk_to_run=float(up),
        run_to_walk=float(down),
        limits=limits,
        first_swing=0 if sc.first_swing == "left" else 1,
    )


def _width_limits(given: Any, foot: tuple[float, float], width: float) -> tuple[float, float]:
    """The (min, max) lateral distance of consecutive footholds, m: ``given``, else from the sole width
    plus :data:`SOLE_CLEARANCE` of it (side by side, the soles do not touch) or half the step width,
    whichever is more, to twice the step width, the range holding the step width itself. A wider
    clearance (it was 0.2 sole widths) left the OP3 no way to stop: its stance is 0.095 m wide with
    soles 0.078 m wide, and the step before its stop must land 0.087 m from the other foot to bring
    the sway to rest; with a minimum of 0.094 m every stop was postponed ("no rest within the limits
    yet") until the run's time ran out.

    Raises:
        InputError: a given range that does not hold the step width.
    """
    if given:
        lo, hi = float(given[0]), float(given[1])
        if not lo <= width <= hi:
            raise InputError("limits.width", list(given), f"a range that holds the step width {width:.4f} m")
        return lo, hi
    return min(max((1.0 + SOLE_CLEARANCE) * foot[1], 0.5 * width), width), 2.0 * width


def _default_speeds(
    sgl: float, max_stride: float, timing: Timing, gait: str, accel: float
) -> tuple[float, float, float]:
    """The default (forward, backward, lateral) speed limits, m/s: sqrt(Fr g l) of
    :data:`FROUDE_SPEED`, the forward one at most what the stride limit holds in the fastest gait the
    scenario allows: ``max_stride`` over its steady step period (running: single support + flight;
    walking: single + double support), less one step's speed change ``accel`` (the step that reaches
    the speed still carries the orbit of the last one). Above it the plans compromise step after step,
    drift off the orbit and no stop reaches rest: the G1 (0.90 m / 0.392 s = 2.30 m/s, 0.26 m/s per
    step) ran away on a held command of 2.3 m/s and more, and reached its stop with compromises at
    2.25 m/s; the limit is 2.04 m/s."""
    fwd, back, side = (math.sqrt(f) * sgl for f in FROUDE_SPEED)
    period = timing.walk_single + timing.double if gait == "walk" else timing.run_single + timing.flight
    return min(fwd, max_stride / period - accel), back, side
