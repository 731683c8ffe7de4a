"""Foot contact fused from the sole force, the sole's height and speed from the estimate, the plan and the
IMU's specific force.

The truth a contact estimate is scored against is "the sole carries a nonzero normal force", and a
force signal with noise ``s`` (std per sample) cannot tell a sole carrying ``< 2 s`` from an unloaded
one: at touch-down (a swing sole that grazes the floor before its planned touch-down), before lift-off
(a sole rolling onto its toe) and while standing on one leg with the other sole resting on the floor.
Following the fusion of gait phase, foot height and force of Bledt et al. (IROS 2018, "Contact model
fusion for event-based locomotion") and the probabilistic contact of Camurri et al. (RA-L 2017), each
sole's flag ``c_i`` combines, per tick:

* the force ``f_i`` (latest sample) and its mean ``fbar_i`` over the last ``window`` samples;
* ``planned_i``: the contact flag of the controller's own plan at this tick (the schedule it
  commands, never the simulator's);
* the height ``dz_i = z_i - z_g`` of the sole's lowest contact point above the ground level ``z_g``,
  both from the estimate (``z = p_z + e_z . R (y + R_s p_j)`` over the sole's contact points ``p_j``);
  ``z_g`` is the lowest-point height of the last sole that was on with a confident force
  (``f > on``), so errors common to both soles (the unobservable drift of the base height) cancel;
* ``vz_i``: the sole centre's estimated vertical speed;
* ``a_v``: the IMU's specific force along the world vertical (the flight rule, "Flight" below).

The rules (a Schmitt trigger on the force whose switching depends on the other cues)::

    rest_i = |dz_i| < near and |vz_i| < still                            the sole rests at the ground level
    off -> on  if fbar_i > on  or  (planned_i and rest_i)  or  (|dz_i| < near and S_i > cusum_h)
                  or  (armed_i and |dz_i| < near and c_j and vz_i > -land)   a landing (c_j: the other sole)
    on -> off  if g_i < off  and not rest_i  and not (landing_i and |dz_i| < near),
               g_i = fbar_i if planned_i else min(fbar_i, f_i)
    off        whenever veto_i = not planned_i and (lifted_i or |v_i| > swing or airborne_i)
    lifted_i = z_i - z_s,i > lift and vz_i > still                      (it rose off its floor)
    S_i = max(0, S_i + (d / s^2) (f_i - d / 2)),  d = cusum_shift s       (reset when on or not near)

``S_i`` is Page's CUSUM, the log-likelihood ratio of a force of mean ``d`` against zero mean (white
Gaussian noise of std ``s``): a small sustained load on a sole at floor level (a graze) is detected
after ``~ 2 cusum_h / (d / s)^2`` ticks, while a sole higher than ``near`` never switches on without
the plain threshold. In the plan's swing, a sole whose latest force sample is already below ``off``
is released at once (a running lift-off unloads the sole in one tick; the mean lags one tick).
``z_s,i`` is sole ``i``'s own lowest-point height at its last tick on, still (``|vz_i| < still``),
with a confident force: a rigid floor does not let a loaded sole's lowest point rise, so a sole of
the plan's swing whose lowest point has risen ``lift`` above where it stood, still rising, has left
the floor whatever its force says (a force from the motors' torques lags the lift-off by its window,
:mod:`gaitshift.control.estimation.torque_contact`). The sole's own stand, not the ground level, so
that a sole leaving a higher tread is not taken for a lifted one.
A sole of the plan's swing whose centre moves faster than ``swing`` (its estimated world speed
``|v_i|``, m/s) carries no load either: a loaded sole on a rigid floor is still, or slides, or rolls
over its toe, and the centre of a rolling sole moves at ``|omega| L / 2`` (measured, G1 tour with sole
force sensors: the truth's contacts in the plan's swing move at most 0.62 m/s; its swing soles reach
4 m/s). That is what a force from the motors' torques misreads: during a fast swing, eq. (2) of
:mod:`~gaitshift.control.estimation.torque_contact` over its window read 26-42 N on a sole 0.15 m up,
moving at 4 m/s, and the scheduler took it for an early touch-down (G1 tour, seed 0, 11.02 s: the
robot fell 0.64 s later). ``veto_i`` releases the force trigger's stance flag at the next tick too
(:meth:`gaitshift.control.estimation.contact.ContactDetector.release`), so neither the base filter
nor the scheduler take such a sole for a stance.
A sole that is on stays on while it rests at the ground level (a graze found by the CUSUM, a sole
unloaded before its lift-off); one that is off needs the plan's stance to switch on from rest alone.
Without a plan (``planned=None``) the plan's rest and swing rules are off.

**Landing.** ``armed_i``: sole ``i`` is off and its lowest point has risen more than ``lift`` above the
ground level since it was last on (it left the floor). An armed sole whose lowest point comes back to
within ``near`` of the ground level while the other sole is on has landed, whatever the plan's
schedule and the force say, and a landing holds it on (``landing_i``, :attr:`ContactFusion.landing`)
while it stays within ``near`` until its mean force confirms it (``fbar_i > on``; the usual rules from
then on) or the veto releases it. A foot lands heel or edge first and grazes the floor with a few
newtons for 5-20 ms before its load comes, often before the plan's touch-down (G1 walk, seed 0: 1-10 N
over 10 ticks, the sole's centre still descending at 30-130 mm/s, so neither ``rest_i`` nor the force
can tell it); the foot scheduler takes its touch-downs from a landing too (docs/estimation.md,
"Touch-downs from a landing"). The ground level is the loaded sole's lowest point, pressed into the
floor, so a landing is seen 2-4 ticks before the first force (g1-walk, seeds 0 and 2). A swing sole
does not come within ``near`` of the ground level before it lands unless it scuffs the floor, or
passes that level on its way down to a lower tread: it then descends faster than ``land``
(:data:`LAND_SPEED`; a landing sole is slower). The
other sole must be on: after a flight the ground level is a height remembered across a phase where
nothing observes the base height, and the estimate drifts there by far more than ``near``
(g1-top-speed, seed 0: the landing sole's estimated lowest point crossed the remembered ground level
76 mm above the floor, 23 ticks before it touched).

**Flight.** In a flight no sole carries anything and the whole body falls freely: its centre of mass
feels no specific force, and the IMU on the pelvis feels only what the legs' motion relative to it
makes, which lifting the legs after a take-off makes negative (the G1 running, g1-run seed 1: the
pelvis's vertical specific force is -6.4 to -2.0 m/s^2 through its flights (1st-99th percentile),
3.7 m/s^2 or more on 95 % of its single-support ticks). So the IMU's specific force along the world
vertical, ``a_v = e_z . R a_imu``, sees a take-off within a tick, where a force from the motors'
torques lags it by its window (a median 6 ticks, 9 at p90, on g1-run). The flight rule is a Schmitt
trigger on it with the thresholds ``flight_on`` < ``flight_off``:

    flight  on  if a_v < flight_on,  off  if a_v > flight_off
    airborne_i = sole i was on when the flight began       (cleared when the flight ends)

and ``veto_i`` also holds for an airborne sole in the plan's swing. Only the soles on at the take-off
are released: a running touch-down loads its sole with 15-25 % of the weight for 5-10 ms while the
pelvis still reads ``a_v < 0`` (g1-run: -2 to -0.2 m/s^2 with 50-90 N on the heel), and a sole that
comes on in the flight is that landing; the wide hysteresis keeps the flight on through it, so the
landing does not start a new flight that would release it.

The height cue only adds contact where the force is ambiguous: a sole far from the ground level
(a stair, a ramp, a drifting height) falls back to the force trigger alone.
"""

from __future__ import annotations

import math

import numpy as np

from gaitshift.control.estimation.types import FLAG_PAIRS
from gaitshift.errors import InputError

#: |dz| below this is "at the ground level", m: ~3 std of the relative height of two soles in the
#: estimate (0.23 mm with typical sensors on g1-walk-run-walk; docs/estimation.md)
NEAR_HEIGHT = 0.8e-3
#: |vz| below this is a resting sole, m/s
STILL_SPEED = 0.05
#: rise of a sole's lowest point above where it stood that makes it lifted, m: ~9 std of the
#: relative height of the soles in the estimate (NEAR_HEIGHT)
LIFT_HEIGHT = 2e-3
#: world speed of a sole's centre above which a sole in the plan's swing carries no load, m/s (module
#: docstring: 0.62 m/s is the fastest loaded sole measured in the plan's swing)
SWING_SPEED = 1.0
#: vertical speed of a sole's centre, m/s, above which a sole descending through the ground level passes
#: it and does not land on it (module docstring, "Landing": landing soles measured at 0.03-0.19 m/s; soles
#: passing an upper tread's level on g1-stairs-down, seed 0, at 0.55-0.81 m/s)
LAND_SPEED = 0.3
#: the flight rule's thresholds on the IMU's vertical specific force, in g (module docstring, "Flight"):
#: below FLIGHT_ON the body is in a flight, above FLIGHT_OFF a sole carries it again
FLIGHT_ON, FLIGHT_OFF = -0.1, 0.3
#: CUSUM target shift in std of one force sample, and its decision threshold (log-likelihood ratio)
CUSUM_SHIFT, CUSUM_THRESHOLD = 0.7, 2.0


class ContactFusion:
    """Stance flags of the two soles from force, plan, sole height and speed (module docstring).

    Args:
        on_force, off_force: switch-on / switch-off thresholds of the mean force, N (``off < on``).
        force_std: std of one force sample, N (> 0).
        window: samples of the mean force (>= 1).
        near: height band of the ground level, m; still: vertical speed of a resting sole, m/s.
        gravity: g, m/s^2 (the flight rule's thresholds are FLIGHT_ON g and FLIGHT_OFF g).
    """

    def __init__(
        self,
        on_force: float,
        off_force: float,
        force_std: float,
        window: int = 1,
        near: float = NEAR_HEIGHT,
        still: float = STILL_SPEED,
        gravity: float = 9.81,
    ):
        if not 0.0 <= off_force < on_force:
            raise InputError("contact.off_force", off_force, f"0 <= off_force < on_force = {on_force}")
        if not (math.isfinite(force_std) and force_std > 0):
            raise InputError("contact.force_std", force_std, "a force noise std > 0 N")
        if int(window) != window or window < 1:
            raise InputError("contact.window", window, "an integer >= 1 (samples)")
        self.on_force, self.off_force, self.window = float(on_force), float(off_force), int(window)
        self.near, self.still = float(near), float(still)
        self.flight_on, self.flight_off = FLIGHT_ON * float(gravity), FLIGHT_OFF * float(gravity)
        d = CUSUM_SHIFT * force_std
        self.cusum_gain, self.cusum_half = d / force_std**2, d / 2.0  # CUSUM increment (f - half) gain
        self.reset()

    def reset(self, contact: tuple[bool, bool] | np.ndarray = (False, False)) -> None:
        """Set the flags (2,); forget the force means, the CUSUMs and the ground level."""
        self._state = [bool(contact[0]), bool(contact[1])]
        self._recent: list[list[float]] = [[], []]
        self._cusum = [0.0, 0.0]
        self.ground: float | None = None
        self._stand: list[float | None] = [None, None]
        #: per sole (2,): the kinematics rule out a load at this tick (module docstring, ``veto_i``)
        self.veto = [False, False]
        self._armed = [False, False]  # module docstring, "Landing"
        #: per sole (2,): on by a landing, its force not yet confirming it (module docstring, ``landing_i``)
        self.landing = [False, False]
        #: the body is in a flight (module docstring, "Flight"); per sole (2,): it was on when the flight began
        self.flight = False
        self.airborne = [False, False]

    def update(
        self,
        force: np.ndarray,
        height: np.ndarray,
        vz: np.ndarray,
        planned: np.ndarray | None = None,
        speed: np.ndarray | None = None,
        specific_force: float | None = None,
    ) -> np.ndarray:
        """One tick: normal forces (2,) N, lowest-point heights (2,) m, vertical speeds (2,) m/s and
        world speeds (2,) m/s (None: ``|vz|``) of the soles (estimate, world frame), the plan's contact
        flags (2,) or None, the IMU's specific force along the world vertical, m/s^2 (None: no flight
        rule); the flags (2,) bool, a shared read-only array."""
        speeds = None if speed is None else speed.tolist()
        return self.update_values(force.tolist(), height.tolist(), vz.tolist(), planned, speeds, specific_force)

    def update_values(
        self,
        forces: list[float],
        heights: list[float],
        vz: list[float],
        planned: np.ndarray | None = None,
        speeds: list[float] | None = None,
        specific_force: float | None = None,
    ) -> np.ndarray:
        """:meth:`update` with the forces, heights and speeds as plain floats (2,) each (the estimator's
        per-tick path)."""
        plans = (True, True) if planned is None else planned.tolist()
        has_plan = planned is not None
        if specific_force is not None:
            self._flight(specific_force)
        v = [abs(vz[0]), abs(vz[1])] if speeds is None else speeds
        left = self._sole(0, forces[0], heights[0], vz[0], v[0], plans[0], has_plan)
        right = self._sole(1, forces[1], heights[1], vz[1], v[1], plans[1], has_plan)
        on = self.on_force
        loaded_l, loaded_r = left and forces[0] > on, right and forces[1] > on
        if loaded_l or loaded_r:
            self.ground = (heights[0] + heights[1]) / 2 if loaded_l and loaded_r else heights[0 if loaded_l else 1]
        for i, loaded in ((0, loaded_l), (1, loaded_r)):
            if loaded and -self.still < vz[i] < self.still:
                self._stand[i] = heights[i]
        return FLAG_PAIRS[left, right]

    def _flight(self, a_v: float) -> None:
        """The flight rule's Schmitt trigger on the vertical specific force ``a_v`` (m/s^2), and the soles
        airborne with it (module docstring, "Flight")."""
        began = not self.flight and a_v < self.flight_on
        self.flight = a_v <= self.flight_off if self.flight else began
        if began:
            self.airborne = [self._state[0], self._state[1]]
        elif not self.flight:
            self.airborne = [False, False]

    def _sole(self, i: int, f: float, height: float, v: float, speed: float, plan: bool, has_plan: bool) -> bool:
        """The rules of the module docstring for sole ``i``: its new flag."""
        recent = self._recent[i]
        recent.append(f)
        if len(recent) > self.window:
            del recent[0]
        mean = sum(recent) / len(recent)
        ground = self.ground
        near = ground is not None and abs(height - ground) < self.near
        rest = near and -self.still < v < self.still
        stand = self._stand[i]
        lifted = stand is not None and height - stand > LIFT_HEIGHT and v > self.still
        veto = self.veto[i] = has_plan and not plan and (lifted or speed > SWING_SPEED or self.airborne[i])
        landing = self.landing[i] and near
        if veto:
            on = landing = False
            self._cusum[i] = 0.0
        elif self._state[i]:
            on = (mean if plan else min(mean, f)) >= self.off_force or (rest and has_plan) or landing
            self._cusum[i] = 0.0
        elif near:
            landing = self._armed[i] and self._state[1 - i] and v > -LAND_SPEED
            s = max(0.0, self._cusum[i] + self.cusum_gain * (f - self.cusum_half))
            on = mean > self.on_force or (rest and plan and has_plan) or s > CUSUM_THRESHOLD or landing
            self._cusum[i] = 0.0 if on else s
        else:
            on = mean > self.on_force
            self._cusum[i] = 0.0
        self._state[i] = on
        self.landing[i] = landing and mean <= self.on_force
        self._armed[i] = not on and (self._armed[i] or (ground is not None and height - ground > LIFT_HEIGHT))
        return on
