"""Foot contact from a per-sole normal-force signal: a moving average, then a Schmitt trigger with debounce.

Per foot, with ``W = m g`` the robot weight and ``f`` the mean of the last ``window`` force samples::

    off -> on   after ``debounce`` consecutive ticks with f > on_fraction  * W
    on  -> off  after ``debounce`` consecutive ticks with f < off_fraction * W

The gap between the two thresholds (hysteresis) keeps force noise near one threshold from toggling the
state; the debounce rejects single-tick spikes (impacts, noise) at the cost of ``debounce - 1`` ticks of
delay. Contact is never read from the simulator's contact list: only the force signal a real robot has.

Thresholds from the noise (:func:`noise_thresholds`): with white force noise of std ``s W`` per
sample, the mean of ``n`` samples has std ``s_n = s / sqrt(n)``; switching on above ``k_on s_n`` makes a
false touchdown of an unloaded sole a ``k_on``-sigma event (``Q(4) = 3e-5`` per tick), switching off
below ``k_off s_n`` releases a sole that carries nothing with probability ``Phi(k_off)`` per tick
(``Phi(1.5) = 0.93``) while a sole that carries more than ``(k_off + 2) s_n`` stays on (a sole
carrying less is below what the sensor can tell from nothing).
"""

from __future__ import annotations

import math

import numpy as np

from gaitshift.control.estimation.types import FootForces
from gaitshift.errors import InputError

#: switch-on / switch-off thresholds in std of the averaged force noise (module docstring)
ON_SIGMAS, OFF_SIGMAS = 4.0, 1.5
#: the force signal's resolution, fraction of the weight: the noise floor of a noise-free profile
FORCE_RESOLUTION = 1e-3


def noise_thresholds(force_std: float, window: int) -> tuple[float, float]:
    """(on, off) thresholds, fractions of the weight, for a force noise of std ``force_std`` (fraction
    of the weight, per sample) averaged over ``window`` samples (module docstring)."""
    if not (math.isfinite(force_std) and force_std >= 0):
        raise InputError("contact.force_std", force_std, "a noise std >= 0 (fraction of the weight)")
    if int(window) != window or window < 1:
        raise InputError("contact.window", window, "an integer >= 1 (samples)")
    s = max(force_std, FORCE_RESOLUTION) / math.sqrt(window)
    return ON_SIGMAS * s, OFF_SIGMAS * s


class ContactDetector:
    """Stance flags of the two soles from their normal forces (see module docstring).

    Args:
        weight: robot weight ``m g``, N.
        on_fraction: switch-on threshold as a fraction of the weight.
        off_fraction: switch-off threshold, fraction of the weight, ``< on_fraction``.
        debounce: consecutive ticks a threshold must be crossed before the state flips (>= 1).
        window: samples of the moving average before the trigger (>= 1; 1 = the raw signal).
    """

    def __init__(
        self,
        weight: float,
        on_fraction: float = 0.15,
        off_fraction: float = 0.05,
        debounce: int = 2,
        window: int = 1,
    ):
        if not weight > 0:
            raise InputError("contact.weight", weight, "a weight > 0 N")
        if not 0.0 <= off_fraction < on_fraction:
            raise InputError("contact.off_fraction", off_fraction, f"0 <= off_fraction < on_fraction = {on_fraction}")
        if int(debounce) != debounce or debounce < 1:
            raise InputError("contact.debounce", debounce, "an integer >= 1 (ticks)")
        if int(window) != window or window < 1:
            raise InputError("contact.window", window, "an integer >= 1 (samples)")
        self.on_force = on_fraction * weight
        self.off_force = off_fraction * weight
        self.debounce = int(debounce)
        self.window = int(window)
        self._state = [False, False]
        self._count = [0, 0]
        self._recent: list[list[float]] = [[], []]

    def reset(self, contact: tuple[bool, bool] | np.ndarray = (False, False)) -> None:
        """Set the stance flags (2,) and clear the debounce counters and the average."""
        self._state = [bool(contact[0]), bool(contact[1])]
        self._count = [0, 0]
        self._recent = [[], []]

    @property
    def contact(self) -> np.ndarray:
        """Current stance flags (2,) bool."""
        return np.array(self._state)

    def update(self, forces: FootForces) -> np.ndarray:
        """Feed one tick of forces; return the stance flags (2,) bool after this tick."""
        return np.array(self.update_values(forces.normal.tolist()))

    def release(self, soles: list[bool]) -> None:
        """Switch the flagged soles (2,) off and clear their debounce: the kinematics ruled their load out
        (``veto`` of :mod:`gaitshift.control.estimation.contact_fusion`)."""
        for i in (0, 1):
            if soles[i]:
                self._state[i] = False
                self._count[i] = 0

    def update_values(self, normal: list[float]) -> tuple[bool, bool]:
        """:meth:`update` on the forces as plain floats (2,) N (the estimator's per-tick path); the flags."""
        state, count, n = self._state, self._count, self.window
        for i, sample in enumerate(normal):
            f = sample
            if n > 1:
                recent = self._recent[i]
                recent.append(sample)
                if len(recent) > n:
                    del recent[0]
                f = sum(recent) / len(recent)
            crossing = f < self.off_force if state[i] else f > self.on_force
            count[i] = count[i] + 1 if crossing else 0
            if count[i] >= self.debounce:
                state[i] = not state[i]
                count[i] = 0
        return state[0], state[1]
