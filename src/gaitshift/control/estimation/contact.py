"""Foot contact from a per-sole normal-force signal: a Schmitt trigger with debounce.

Per foot, with ``W = m g`` the robot weight and ``f`` the measured normal force::

    off -> on   after ``debounce`` consecutive ticks with f > on_fraction  * W
    on  -> off  after ``debounce`` consecutive ticks with f < off_fraction * W

The gap between the two thresholds (hysteresis) keeps force noise near one threshold from toggling the
state; the debounce rejects single-tick spikes (impacts, noise) at the cost of ``debounce - 1`` ticks of
delay. Contact is never read from the simulator's contact list: only the force signal a real robot has.
"""

from __future__ import annotations

import numpy as np

from gaitshift.control.estimation.types import FootForces
from gaitshift.errors import InputError


class ContactDetector:
    """Stance flags of the two soles from their normal forces (see module docstring).

    Args:
        weight: robot weight ``m g``, N.
        on_fraction: switch-on threshold as a fraction of the weight.
        off_fraction: switch-off threshold, fraction of the weight, ``< on_fraction``.
        debounce: consecutive ticks a threshold must be crossed before the state flips (>= 1).
    """

    def __init__(self, weight: float, on_fraction: float = 0.15, off_fraction: float = 0.05, debounce: int = 2):
        if not weight > 0:
            raise InputError("contact.weight", weight, "a weight > 0 N")
        if not 0.0 <= off_fraction < on_fraction:
            raise InputError("contact.off_fraction", off_fraction, f"0 <= off_fraction < on_fraction = {on_fraction}")
        if int(debounce) != debounce or debounce < 1:
            raise InputError("contact.debounce", debounce, "an integer >= 1 (ticks)")
        self.on_force = on_fraction * weight
        self.off_force = off_fraction * weight
        self.debounce = int(debounce)
        self._state = [False, False]
        self._count = [0, 0]

    def reset(self, contact: tuple[bool, bool] | np.ndarray = (False, False)) -> None:
        """Set the stance flags (2,) and clear the debounce counters."""
        self._state = [bool(contact[0]), bool(contact[1])]
        self._count = [0, 0]

    @property
    def contact(self) -> np.ndarray:
        """Current stance flags (2,) bool."""
        return np.array(self._state)

    def update(self, forces: FootForces) -> np.ndarray:
        """Feed one tick of forces; return the stance flags (2,) bool after this tick."""
        state, count = self._state, self._count
        for i, f in enumerate(forces.normal.tolist()):
            crossing = f < self.off_force if state[i] else f > self.on_force
            count[i] = count[i] + 1 if crossing else 0
            if count[i] >= self.debounce:
                state[i] = not state[i]
                count[i] = 0
        return np.array(state)
