"""Model errors of the simulated robot: the plant's masses scaled while the controller keeps the nominal
model (``SimOptions.mass_scale``).

With scale ``s``, every body's mass ``m_b`` and rotational inertia ``I_b`` (about its own frame) become
``s m_b`` and ``s I_b`` in the PHYSICS model only (a uniform change of density: the CoM positions stay),
so the whole-body controller, which plans its torques with the nominal model, meets a robot ``s`` times
heavier (``s > 1``) or lighter (``s < 1``) than it believes. Total mass: ``s M``.
"""

from __future__ import annotations

import copy
import math
from typing import Any

from gaitshift.errors import InputError

#: allowed mass scale factors, inclusive
MASS_SCALE_RANGE = (0.25, 4.0)

__all__ = ["MASS_SCALE_RANGE", "check_mass_scale", "scaled_masses"]


def check_mass_scale(scale: object) -> float:
    """``scale`` as a float in :data:`MASS_SCALE_RANGE`.

    Raises:
        InputError: not a finite number in the range.
    """
    lo, hi = MASS_SCALE_RANGE
    ok = isinstance(scale, int | float) and not isinstance(scale, bool) and math.isfinite(scale)
    if not ok or not lo <= float(scale) <= hi:  # type: ignore[arg-type]
        raise InputError("mass_scale", scale, f"a number in [{lo:g}, {hi:g}]")
    return float(scale)  # type: ignore[arg-type]


def scaled_masses(model: Any, scale: float) -> Any:
    """A copy of the MuJoCo ``model`` with ``body_mass`` and ``body_inertia`` times ``scale`` (module
    docstring), or ``model`` itself when ``scale`` is 1."""
    if scale == 1.0:
        return model
    out = copy.copy(model)
    out.body_mass[:] = model.body_mass * scale
    out.body_inertia[:] = model.body_inertia * scale
    return out
