"""Model and sensor errors of the simulated robot: the plant's masses scaled while the controller keeps
the nominal model (``SimOptions.mass_scale``), its base's centre of mass moved (``com_offset``), its
motors weaker or stronger (``motor_strength``), and extra joint-velocity noise (``joint_vel_noise``).

With scale ``s``, every body's mass ``m_b`` and rotational inertia ``I_b`` (about its own frame) become
``s m_b`` and ``s I_b`` in the PHYSICS model only (a uniform change of density: the CoM positions stay),
so the whole-body controller, which plans its torques with the nominal model, meets a robot ``s`` times
heavier (``s > 1``) or lighter (``s < 1``) than it believes. Total mass: ``s M``.

Base CoM offset ``c`` (3,) m: the floating base's centre of mass ``body_ipos`` moves by ``c`` in the
base's frame, in the PHYSICS model only (the RL anchors randomise it by about +-5 cm in x and y).

Motor strength ``k``: every actuator's transmission gear (and the joints' actuator-force clamp) is
``k`` times the model's, so the joint torque is ``k tau`` for a commanded ``tau`` and the torque limit
``k tau_max``; the motors' reported ``tau_est``
(the actuator force before the gear) stays ``tau``, as a real driver's current-based estimate with the
nominal torque constant would (the RL anchors: +-10 %).

Joint-velocity noise ``u`` (rad/s): every joint velocity the motor drivers report gets an extra
independent draw ``U(-u, u)`` per tick, on top of the noise profile's own (the form of the ``rl-peer``
profile's +-1.5 rad/s); it acts on the estimated state only (the oracle reads the truth).
"""

from __future__ import annotations

import copy
from dataclasses import replace
from typing import Any

import mujoco
import numpy as np

from gaitshift.control.estimation.noise import Channel, NoiseProfile
from gaitshift.errors import InputError, number_in
from gaitshift.scenario.sim_settings import COM_OFFSET_RANGE, MASS_SCALE_RANGE, MOTOR_STRENGTH_RANGE

#: allowed extra joint-velocity noise, rad/s (half-width of the uniform draw), inclusive
JOINT_VEL_NOISE_RANGE = (0.0, 100.0)

__all__ = [
    "JOINT_VEL_NOISE_RANGE",
    "MASS_SCALE_RANGE",
    "check_com_offset",
    "check_joint_vel_noise",
    "check_mass_scale",
    "check_motor_strength",
    "perturbed_physics",
    "scaled_masses",
    "with_constants",
    "with_joint_vel_noise",
]


def check_mass_scale(scale: object) -> float:
    """``scale`` as a float in :data:`MASS_SCALE_RANGE`, else :class:`InputError`."""
    return number_in("mass_scale", scale, MASS_SCALE_RANGE)


def scaled_masses(model: Any, scale: float) -> Any:
    """A copy of the MuJoCo ``model`` with ``body_mass`` and ``body_inertia`` times ``scale`` (module
    docstring), or ``model`` itself when ``scale`` is 1 (:func:`perturbed_physics` with nothing else changed)."""
    return perturbed_physics(model, scale, (0.0, 0.0, 0.0), 1.0, 0)


def with_constants(model: Any) -> Any:
    """``model`` with the constants MuJoCo derives from its masses at compile time recomputed
    (``mj_setConst``: ``body_subtreemass``, the inverse weights of the constraint solver, ...). Without
    them ``subtree_com = sum_b m_b x_b / body_subtreemass`` divides by the nominal mass: the logged CoM
    of a plant ``s`` times heavier was ``s`` times its position (and its velocity ``s`` times too)."""
    mujoco.mj_setConst(model, mujoco.MjData(model))
    return model


def check_com_offset(offset: object) -> tuple[float, float, float]:
    """``offset`` as three floats (m), each in :data:`COM_OFFSET_RANGE`, else :class:`InputError`."""
    lo, hi = COM_OFFSET_RANGE
    if not isinstance(offset, list | tuple | np.ndarray) or len(offset) != 3:
        raise InputError("com_offset", offset, f"three numbers in [{lo}, {hi}] m (x, y, z in the base frame)")
    vals = [number_in(f"com_offset[{i}]", v, COM_OFFSET_RANGE, "m") for i, v in enumerate(list(offset))]
    return vals[0], vals[1], vals[2]


def check_motor_strength(strength: object) -> float:
    """``strength`` as a float in :data:`MOTOR_STRENGTH_RANGE`, else :class:`InputError`."""
    return number_in("motor_strength", strength, MOTOR_STRENGTH_RANGE)


def perturbed_physics(model: Any, mass_scale: float, com_offset: Any, motor_strength: float, base: int) -> Any:
    """The physics model of the simulated robot (module docstring): ``model`` with its masses times
    ``mass_scale``, body ``base``'s CoM moved by ``com_offset`` (3,) m and the actuator gears times
    ``motor_strength``; ``model`` itself when nothing changes."""
    offset = np.asarray(com_offset, dtype=float)
    if mass_scale == 1.0 and not np.any(offset) and motor_strength == 1.0:
        return model
    out = copy.copy(model)
    out.body_mass[:] = model.body_mass * mass_scale
    out.body_inertia[:] = model.body_inertia * mass_scale
    out.body_ipos[base] = model.body_ipos[base] + offset
    out.actuator_gear[:, 0] = model.actuator_gear[:, 0] * motor_strength
    out.jnt_actfrcrange[:] = model.jnt_actfrcrange * motor_strength  # the joint's own clamp follows
    return with_constants(out)  # once, after every change


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
