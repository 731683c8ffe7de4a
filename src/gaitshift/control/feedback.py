"""Step-level feedback of TV-LIPM plans: capture-point foothold corrections and the plan shift.

While a foot swings (until ``freeze_u`` of its swing) its target is moved by the foothold correction

    delta = k_cp (xi - xi_ref),    xi = c + cd / omega,    omega = sqrt(g / h)

(xi: the divergent component of motion, or instantaneous capture point, of the LIPM; h the plan's CoM
height), horizontal, with ``xi`` measured and ``xi_ref`` that of the shifted plan. With
``predict_touchdown``, the error is the one predicted at the touchdown: on the other foot's stance the
LIPM's divergent component moves away from its foothold as ``xi' = omega (xi - p)``, so an error grows
as ``exp(omega tau)`` until that stance ends or the swing foot lands, ``tau`` = the shorter of the two
times left (0 when the other foot is not on the ground):

    delta = k_cp (xi - xi_ref) exp(omega tau).

With ``cop_room`` the prediction lets the stance sole do what the whole-body controller makes it do:
move its centre of pressure off the planned ZMP (the plan's sole centre in single support) to take the
error back. With the CoP held at the edge of a sole of half sizes ``d`` (heading frame, per axis), the
LIPM's divergent component obeys ``e' = omega (e - d sign e)`` (Koolen et al. 2012, capturability with
a finite-sized foot, eq. 9), so an error |e| > d grows and a smaller one is taken back by the ankle:

    |e(tau)| = max(0, |e| exp(omega tau) - d (exp(omega tau) - 1)),   sign kept,

which is the plain exp(omega tau) for d = 0 and the current error for tau = 0. Both are the LIPM's
divergent component with the CoP held at an offset ``c`` from the planned ZMP over ``tau``,

    e(tau) = e exp(omega tau) - c (exp(omega tau) - 1),   per heading axis, 0 once it would change sign

(:func:`dcm_error_after`), with ``c = d sign e``. By default (``commanded_cop``) ``c`` is the offset the
whole-body controller gave the stance sole's CoP on its last tick (:meth:`TickInfo.cop_offset`), held
over ``tau``, as far as it takes the error back (per heading axis, on the error's side; else 0,
:func:`taking_back`): the ankle is expected to keep doing what it does, not to go to its edge. The
other side is left out because the QP also rolls the CoP from heel to toe for the whole body's own
dynamics (std 2.3 cm along the sole in single support of an undisturbed g1-walk, where the plan's ZMP
sits at the sole centre); extrapolated, that part moved the g1-walk plan 13 cm forward over its ten
steps (6.5 cm without it, 5.1 cm with the plain exp(omega tau); docs/simulation.md). ``d`` is the CoP's room:
the sole's half size, or less where the leg's motors cannot hold the moment at the load the plan puts
on the sole over ``tau`` (:mod:`gaitshift.control.cop_room`: the T1's 20 N m ankles). Without it the step
correction and the controller's CoP both act on the same error, the foot is over-corrected by what the
ankle took back, the plan shift then moves the CoM reference by that much, and the next stance starts
with the error reversed (g1-stairs-down: the feet stepped inward by 3, 5, 12 cm on successive steps,
docs/simulation.md). The corrected
foothold is then kept inside the leg's kinematic limits (reach from the hip at touchdown, no crossing
of the feet: :mod:`gaitshift.control.step_limits`, derived from the robot model) and, if
``max_step_adjust`` is set, the correction is also clipped to it per axis. The correction is
recomputed every tick until ``freeze_u``, so the swing foot re-targets mid-swing.

Across the heading, on a walking step (one that lands into a double support), the part of the error
beyond the stance sole's lateral CoP room (its half width ``d_y``) can get ``lateral_gain`` (off by
default); the rest of it, the error along the heading, and a running step get ``gain`` (1):

    delta_x = k e_x,   delta_y = k e_y + (k_y - k) sign(e_y) max(0, |e_y| - d_y)

(:func:`heading_gain`, heading frame of the plan, ``e`` the predicted error). A lateral error can be
taken back only by the foot on its side: the other foot's correction is clipped by the no-crossing
limit. With k_y = 1 the push-side foot lands at the capture point and the lateral velocity is held,
not removed; after a lateral push of 0.3-0.5 m/s the G1 walked sideways at 0.3-0.8 m/s until the
reach limit bound and it fell (docs/robustness.md, "The mechanism"). Beyond the capture point the
LIPM's divergent component turns back. An error within the sole's half width the ankle takes back
on the next stance (the CoP moves toward it); over-correcting it too made g1-stairs-down (seed 0)
fall at 5.25 s. Measured on the G1 survival spec with k_y = 1.3 against k_y = 1, on the same 1445
cases: 88 falls each (26 cases rescued, 26 new falls, at pushes from 0.03 to 0.49 m/s: the
outcome of a marginal case flips with any small change), so it is not the default
(docs/robustness.md, "The same spec before and after"). Along the heading both feet act: a gain of
1.3 there made g1-top-speed (seed 0) and g1-run-slope-up (seed 1) fall, and 1.3 across on running
steps made g1-top-speed seed 2 fall at 7.71 s (all three hold with 1).

When the foot lands, the whole remaining plan (CoM reference and later footholds) is translated by
its correction, blended in with the first-order lag ``shift' = (target - shift) / shift_time`` (one
explicit Euler step per tick): the plan is re-anchored on where the robot actually stands, as the LIPM
is translation invariant.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from gaitshift.common.rotations import rot2
from gaitshift.control.cop_room import CopRoom
from gaitshift.control.step_limits import StepLimits


@dataclass(frozen=True)
class CaptureSettings:
    """Gain and limits of the capture-point step feedback (see module docstring); ``gain`` 0 turns
    it off."""

    gain: float = 1.0
    # the gain on the lateral error beyond the sole on walking steps (module docstring, "Across the
    # heading"); None: ``gain``. Off by default: 1.3 left the G1 survival map unchanged (docs/robustness.md)
    lateral_gain: float | None = None
    freeze_u: float = 0.7  # swing progress after which the foothold correction is frozen
    shift_time: float = 0.1  # s: time constant of the plan shift after a corrected touchdown
    max_step_adjust: float | None = None  # m per axis; None: the kinematic limits alone
    kinematic_limits: bool = True  # reach and crossing limits (gaitshift.control.step_limits)
    reach_fraction: float = 0.95  # share of the leg length the knee may straighten to (step_limits eq. 1)
    predict_touchdown: bool = True  # the error predicted at the touchdown, exp(omega tau) (module docstring)
    anchor: bool = True  # estimated state: keep the plan on the measured stance soles (PlanShift.anchor_on)
    # on terrain a corrected touchdown keeps this many std of the position estimate (along x) more from
    # its tread's edges (control/reference.py; 0 on the truth)
    edge_sigmas: float = 2.0
    # the predicted error leaves to the stance sole what its centre of pressure can take back (module
    # docstring). Off by default: it holds g1-stairs-down on seeds 0-5 but g1-walk-run-walk then falls on
    # a 0.4 friction floor (8.70 s estimated, 8.85 s oracle; docs/simulation.md, "What decides it")
    cop_room: bool = False
    # the predicted error leaves to the stance sole the part of the CoP offset the whole-body controller
    # commanded on its last tick that takes the error back (module docstring; cop_room takes precedence).
    # On: g1-stairs-down holds on seeds 0-5, its last stance 0.23-0.24 m wide (off: seeds 0 and 5, the
    # last stance up to 0.65 m wide; docs/simulation.md, "Fifth pass")
    commanded_cop: bool = True
    # clearance c, m, of the tandem step: a foothold a short step (L + c to 2L + c along the heading, L
    # the sole length) from the other foot may land in line with it, never across (step_limits eq. 2);
    # None: the sole width at any distance. Lateral pushes toward the stance foot while running:
    # 22.1 N s held with None (estimated and oracle), docs/simulation.md ("Pushes while running")
    tandem_clearance: float | None = 0.01


def dcm_error_after(err: np.ndarray, growth: float, cop: np.ndarray, yaw: float) -> np.ndarray:
    """Divergent-component error (2,) m after ``growth`` = exp(omega tau) >= 1 with the CoP held at the
    offset ``cop`` (2,) m from the planned ZMP (module docstring): ``e'= omega (e - c)`` integrated,
    per axis of the heading frame (heading ``yaw``, rad), and 0 on an axis where it would change sign.
    ``err``, ``cop`` and the result are world-frame."""
    rot = rot2(yaw)
    e, off = rot.T @ err, rot.T @ cop
    after = e * growth - off * (growth - 1.0)
    return np.asarray(rot @ np.where(after * e > 0.0, after, 0.0))


def predicted_error(err: np.ndarray, growth: float, room: np.ndarray, yaw: float) -> np.ndarray:
    """Divergent-component error (2,) m predicted after ``growth`` = exp(omega tau) >= 1 with the
    stance sole's CoP at its edge (module docstring): ``err`` (2,) m in the world frame, ``room`` (2,)
    m how far the CoP can move along and across the sole (:class:`CopRoom`; its heading ``yaw``, rad).
    Returns (2,) m, world frame."""
    return dcm_error_after(err, growth, edge_offset(err, room, yaw), yaw)


def edge_offset(err: np.ndarray, room: np.ndarray, yaw: float) -> np.ndarray:
    """The CoP offset (2,) m, world frame, at the edge of the ``room`` (2,) m (half sizes along and
    across a sole of heading ``yaw``, rad) on the side of the error ``err`` (2,) m, per axis."""
    rot = rot2(yaw)
    return np.asarray(rot @ (np.sign(rot.T @ err) * room))


def taking_back(cop: np.ndarray, err: np.ndarray, yaw: float) -> np.ndarray:
    """The part (2,) m of a CoP offset ``cop`` (2,) m that takes the divergent-component error ``err``
    (2,) m back: per axis of the heading frame (heading ``yaw``, rad), the offset where it lies on the
    error's side, else 0 (module docstring). World frame in and out."""
    rot = rot2(yaw)
    off = rot.T @ cop
    return np.asarray(rot @ np.where(off * (rot.T @ err) > 0.0, off, 0.0))


def heading_gain(
    err: np.ndarray, settings: CaptureSettings, yaw: float, walking: bool = True, room: float = 0.0
) -> np.ndarray:
    """The foothold correction (2,) m for the predicted divergent-component error ``err`` (2,) m, both
    world-frame (module docstring, "Across the heading"): ``gain`` along the heading ``yaw`` (rad); across
    it, on a ``walking`` step (a double support follows the touchdown), ``lateral_gain`` on the part of
    the error beyond the stance sole's lateral CoP ``room`` (m, its half width), ``gain`` on the rest:

    .. math:: \\delta_x = k e_x,\\qquad
              \\delta_y = k e_y + (k_y - k) \\operatorname{sign}(e_y) \\max(0, |e_y| - d_y)

    in the heading frame; a running step has ``gain`` on both axes.
    """
    if not walking or settings.lateral_gain is None:
        return np.asarray(settings.gain * err)
    rot = rot2(yaw)
    e = rot.T @ err
    out = settings.gain * e
    out[1] += (settings.lateral_gain - settings.gain) * np.sign(e[1]) * max(0.0, abs(e[1]) - room)
    return np.asarray(rot @ out)


def capture_point_offset(
    com: np.ndarray,
    com_vel: np.ndarray,
    com_ref: np.ndarray,
    vel_ref: np.ndarray,
    omega: float,
    gain: float,
    limit: float,
) -> np.ndarray:
    """Foothold correction (3,) m = gain (xi - xi_ref), xi = c + cd / omega (horizontal components of
    the CoM position ``com`` (3,) m and velocity ``com_vel`` (3,) m/s, and of their references), z = 0,
    clipped to ``limit`` (m) per axis. ``omega`` = sqrt(g / h), 1/s."""
    xi = com[:2] + com_vel[:2] / omega
    xi_ref = com_ref[:2] + vel_ref[:2] / omega
    out = np.zeros(3)
    out[:2] = np.clip(gain * (xi - xi_ref), -limit, limit)
    return out


@dataclass(frozen=True)
class SwingContext:
    """What the limits of a swinging foot's correction need (:meth:`PlanShift.correct_swings`).

    Attributes:
        footholds: (2, 3) m, each foot's planned foothold of its current (or last) swing (unshifted).
        measured: (2, 3) m, the sole positions as the controller sees them.
        time_left: (2,) s, time to each foot's planned touchdown (>= 0).
        yaw: heading of the plan now, rad.
        stance_left: (2,) s, time to each stance foot's planned lift-off (>= 0; 0 for a swinging foot).
        load_factor: the plan's mean vertical force over the next ``tau`` s in units of the weight,
            ``1 + (zd(t + tau) - zd(t)) / (g tau)`` (:mod:`gaitshift.control.cop_room`); None: 1.
        cop: the CoP offset (2,) m, world frame, the controller gave a stance sole on its last tick
            (:meth:`gaitshift.control.wbc_data.TickInfo.cop_offset`; None: none known).
    """

    footholds: np.ndarray
    measured: np.ndarray
    time_left: np.ndarray
    yaw: float
    stance_left: np.ndarray | None = None
    load_factor: Callable[[float], float] | None = None
    cop: Callable[[int], np.ndarray | None] | None = None

    def double_support_ahead(self, side: int, stance: np.ndarray) -> bool:
        """Whether the swinging foot ``side`` lands while the other foot still stands (a walking step;
        a running step lands after a flight). Without the stance times: True."""
        o = 1 - side
        if self.stance_left is None:
            return True
        return bool(stance[o] and self.stance_left[o] >= self.time_left[side])

    def growth_time(self, side: int, stance: np.ndarray) -> float:
        """tau of the module docstring for the swinging foot ``side``, s."""
        o = 1 - side
        if self.stance_left is None or not stance[o]:
            return 0.0
        return float(max(0.0, min(self.time_left[side], self.stance_left[o])))


class PlanShift:
    """State of the step feedback: the plan translation and the current foothold corrections.

    Attributes:
        shift: (3,) m, translation of the plan applied now (lags behind ``target``).
        target: (3,) m, sum of the corrections of the feet that have landed.
        offset: (2, 3) m, correction of each swinging foot's target (0 for a stance foot).
    """

    def __init__(
        self,
        settings: CaptureSettings,
        omega: float,
        limits: StepLimits | None = None,
        room: CopRoom | tuple[float, float] = (0.0, 0.0),
        weight: float = 1.0,
    ) -> None:
        """``room``: the stance sole's CoP room (:class:`CopRoom`), or its half length and half width, m
        (the sole alone); ``weight``: m g, N (``cop_room``)."""
        self.settings = settings
        self.omega = omega
        cop = room if isinstance(room, CopRoom) else CopRoom.sole_only(room)
        self.half = np.asarray(cop.half, float)  # the sole's half length and half width, m
        self.cop = cop if settings.cop_room and cop.half.any() else None
        self.weight = weight
        self.limits = limits if settings.kinematic_limits else None
        self.shift = np.zeros(3)
        self.target = np.zeros(3)
        self.offset = np.zeros((2, 3))

    def land(self, landed: np.ndarray) -> None:
        """Feet ``landed`` (2,) bool have just touched down: their corrections join the plan shift."""
        for s in (0, 1):
            if landed[s]:
                self.target += self.offset[s]
                self.offset[s] = 0.0

    def anchor_on(self, stance: np.ndarray, measured: np.ndarray, planned: np.ndarray) -> None:
        """Keep the plan attached to the support the robot stands on (``anchor``; every tick).

        With the stance flags ``stance`` (2,) bool and the sole positions (2, 3) m ``measured`` (in the
        controller's world, the estimated one) and ``planned`` (the plan's footholds of the current
        stances), the shift target is the mean offset of the stance soles from their footholds,

        .. math:: s = \\operatorname{mean}_{i \\in stance} (p^{meas}_{i} - p^{plan}_{i}),

        held through flight. That subsumes the commanded corrections (a sole lands where it was sent,
        plus its tracking error) and makes the CoM reference relative to the stance soles, which the
        joint encoders measure well, instead of to the estimated world position, whose errors (1-3 cm
        per step from the IMU integration in swing and flight, and an unobservable drift) would
        otherwise act on the CoM like pushes. The vertical offset is taken too: the estimated base
        height drifts by a few mm per step where the stance sole rolls (2-4 mm per step in g1-tour's
        turning walk, docs/estimation.md), and a CoM height reference kept in the estimated world would
        bend the legs by that much; referred to the stance soles, the CoM height stays the plan's."""
        if not self.settings.anchor or not stance.any():
            return
        self.target[:] = (measured[stance] - planned[stance]).mean(axis=0)

    def blend(self, dt: float) -> None:
        """One step ``dt`` (s) of the lag of ``shift`` toward ``target``."""
        self.shift += (self.target - self.shift) * min(1.0, dt / self.settings.shift_time)

    def _held_cop(self, side: int, tau: float, err: np.ndarray, ctx: SwingContext | None) -> np.ndarray | None:
        """The CoP offset (2,) m (world frame) the stance sole ``side`` is expected to hold for ``tau`` s
        against the divergent-component error ``err`` (2,) m (module docstring): with ``cop_room`` at the
        edge of its room toward the error, else the one the controller commanded (``commanded_cop``);
        None: the plain exp(omega tau) (no stance ahead, or neither setting)."""
        if ctx is None or tau <= 0.0:
            return None
        if self.cop is not None:
            load = ctx.load_factor(tau) if ctx.load_factor is not None else 1.0
            return edge_offset(err, self.cop.at(max(load, 0.1) * self.weight), ctx.yaw)
        if self.settings.commanded_cop and ctx.cop is not None:
            commanded = ctx.cop(side)
            return None if commanded is None else taking_back(commanded, err, ctx.yaw)
        return None

    def correct_swings(
        self,
        stance: np.ndarray,
        progress: np.ndarray,
        com: np.ndarray,
        com_vel: np.ndarray,
        com_plan: np.ndarray,
        vel_plan: np.ndarray,
        ctx: SwingContext | None = None,
    ) -> None:
        """Recompute the correction of each swinging foot before ``freeze_u`` of its swing.

        ``stance`` (2,) bool: feet in stance (left alone); ``progress`` (2,): swing progress u of each
        foot (:meth:`gaitshift.control.schedule.FootScheduler.swing_progress`). ``com``/``com_vel``
        measured, ``com_plan``/``vel_plan`` the plan sample (unshifted), all (3,). With ``ctx`` and
        limits, the corrected foothold is kept inside them (:meth:`StepLimits.clamp`).
        """
        cfg = self.settings
        if cfg.gain <= 0:
            return
        clip = math.inf if cfg.max_step_adjust is None else cfg.max_step_adjust
        for s in (0, 1):
            if stance[s] or progress[s] >= cfg.freeze_u:
                continue
            tau = ctx.growth_time(s, stance) if cfg.predict_touchdown and ctx is not None else 0.0
            growth = math.exp(self.omega * tau)
            err = capture_point_offset(com, com_vel, com_plan + self.target, vel_plan, self.omega, 1.0, math.inf)
            cop = self._held_cop(1 - s, tau, err[:2], ctx)
            yaw = ctx.yaw if ctx is not None else 0.0
            walking = ctx is None or ctx.double_support_ahead(s, stance)
            e = dcm_error_after(err[:2], growth, cop, yaw) if cop is not None else growth * err[:2]
            delta = np.zeros(3)
            delta[:2] = np.clip(heading_gain(e, cfg, yaw, walking, self.half[1]), -clip, clip)
            if self.limits is not None and ctx is not None:
                base = ctx.footholds[s] + self.shift
                o = 1 - s
                other = ctx.measured[o] if stance[o] else ctx.footholds[o] + self.shift + self.offset[o]
                hip_com = com + ctx.time_left[s] * com_vel
                delta = self.limits.clamp(s, base + delta, hip_com, ctx.yaw, other) - base
                delta[2] = 0.0
            self.offset[s] = delta
