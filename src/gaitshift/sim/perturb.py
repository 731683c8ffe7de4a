"""Model and sensor errors of the simulated robot: the plant's masses scaled while the controller keeps
the nominal model (``SimOptions.mass_scale``), and extra joint-velocity noise (``joint_vel_noise``).

With scale ``s``, every body's mass ``m_b`` and rotational inertia ``I_b`` (about its own frame) become
``s m_b`` and ``s I_b`` in the PHYSICS model only (a uniform change of density: the CoM positions stay),
so the whole-body controller, which plans its torques with the nominal model, meets a robot ``s`` times
heavier (``s > 1``) or lighter (``s < 1``) than it believes. Total mass: ``s M``.

Joint-velocity noise ``u`` (rad/s): every joint velocity the motor drivers report gets an extra
independent draw ``U(-u, u)`` per tick, on top of the noise profile's own (the form of the ``rl-peer``
profile's +-1.5 rad/s); it acts on the estimated state only (the oracle reads the truth).
"""

from __future__ import annotations

import copy
from dataclasses import replace
from typing import Any

from gaitshift.control.estimation.noise import Channel, NoiseProfile
from gaitshift.errors import number_in
from gaitshift.scenario.sim_settings import MASS_SCALE_RANGE

#: allowed extra joint-velocity noise, rad/s (half-width of the uniform draw), inclusive
JOINT_VEL_NOISE_RANGE = (0.0, 100.0)

__all__ = [
    "JOINT_VEL_NOISE_RANGE",
    "MASS_SCALE_RANGE",
    "check_joint_vel_noise",
    "check_mass_scale",
    "scaled_masses",
    "with_joint_vel_noise",
]


def check_mass_scale(scale: object) -> float:
    """``scale`` as a float in :data:`MASS_SCALE_RANGE`, else :class:`InputError`."""
    return number_in("mass_scale", scale, MASS_SCALE_RANGE)


def scaled_masses(model: Any, scale: float) -> Any:
    """A copy of the MuJoCo ``model`` with ``body_mass`` and ``body_inertia`` times ``scale`` (module
    docstring), or ``model`` itself when ``scale`` is 1."""
    if scale == 1.0:
        return model
    out = copy.copy(model)
    out.body_mass[:] = model.body_mass * scale
    out.body_inertia[:] = model.body_inertia * scale
    return out


def check_joint_vel_noise(noise: object) -> float:
    """``noise`` as a float in :data:`JOINT_VEL_NOISE_RANGE` (rad/s), else :class:`InputError`."""
    return number_in("joint_vel_noise", noise, JOINT_VEL_NOISE_RANGE, "rad/s")


def with_joint_vel_noise(profile: NoiseProfile, noise: float) -> NoiseProfile:
    """``profile`` with ``noise`` rad/s more uniform half-width on the driver velocity (module
    docstring); ``profile`` itself when ``noise`` is 0."""
    if noise == 0.0:
        return profile
    jv = profile.joint_vel
    return replace(profile, joint_vel=Channel(density=jv.density, uniform=jv.uniform + float(noise)))
