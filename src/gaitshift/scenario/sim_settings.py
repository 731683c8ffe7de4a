"""The ``sim:`` block of a scenario: how ``gaitshift simulate`` runs it (sensing, latency, floor).

Every key is optional; a key left out keeps the simulator's default (``SimOptions``), and a command-line
flag overrides the key. Example::

    sim: {state: estimated, noise: rl-peer, noise_scale: 0.5, latency: 4, friction: 0.35, seed: 3}

Perturbations (issue 13; the controller is never told them)::

    sim:
      mass_scale: 1.1            # masses of the simulated robot only
      com_offset: [0.02, -0.01, 0]   # m, the base's centre of mass in the simulated robot only
      motor_strength: 0.9        # factor on the simulated motors' torque and torque limit
      joint_vel_noise: 0.5       # rad/s, extra uniform joint-velocity sensor noise
      pushes: [{t: 2.0, impulse: [0, 15, 0], duration: 0.1}]   # N s, world frame, from plan time t
      bumps: [{x: 1.5, height: 0.03, length: 0.2}]             # m, box on the floor from x
      terrain: blind             # the planner is not told the scenario's terrain (TERRAIN_KNOWLEDGE)
      replan_lead: 0.1           # s, perceived: each re-plan made this long before its boundary
      footholds: plane           # perceived: footholds judged on the map in 2-D (FOOTHOLD_RULES)
      known_floor: true          # the controller is told that a world without terrain is the flat floor

The allowed values live here (the lowest layer) and the simulator checks its options against them.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import Field, Strict

from gaitshift.errors import InputError
from gaitshift.scenario.fields import StrictModel

#: what the controller sees: the estimator's state, or the simulator's truth
STATE_SOURCES = ("estimated", "oracle")
#: where the controller's contact sensing comes from: the soles' force sensors, or the motors' torques
CONTACT_SOURCES = ("force", "torque")
#: what the planner is told of the scenario's ``terrain:`` (the world is always built on it): ``known``
#: (the planner plans on it), ``blind`` (the planner plans on flat ground), ``perceived`` (the blind plan's
#: footholds moved onto the controller's elevation map as it grows; TV-LIPM scenarios)
TERRAIN_KNOWLEDGE = ("known", "blind", "perceived")
#: how a perceived foothold is placed (:mod:`gaitshift.control.perceived_driver`): on the map's profile
#: along the path alone, or judged on the map in 2-D first
FOOTHOLD_RULES = ("profile", "plane")
#: sensor noise profiles (``none``: exact readings)
NOISE_PROFILES = ("none", "typical", "rl-peer")
#: friction coefficients (floor, assumed), inclusive
FRICTION_RANGE = (0.01, 5.0)
#: noise scale factor, inclusive
NOISE_SCALE_RANGE = (0.0, 1000.0)
#: loop latency, ticks, inclusive
LATENCY_RANGE = (0, 50)
#: mass scale factor of the simulated robot, inclusive (the simulator checks the same range)
MASS_SCALE_RANGE = (0.25, 4.0)
#: offset of the floating base's centre of mass in the simulated robot, m per axis, inclusive
COM_OFFSET_RANGE = (-0.2, 0.2)
#: factor on the simulated motors' torque (and torque limit), inclusive
MOTOR_STRENGTH_RANGE = (0.25, 2.0)


def check_friction(field: str, mu: Any) -> None:
    """:class:`~gaitshift.errors.InputError` unless ``mu`` is None or a friction coefficient in
    :data:`FRICTION_RANGE` (the floor's ``friction``, the controller's ``assumed_friction``)."""
    lo, hi = FRICTION_RANGE
    if mu is not None and (isinstance(mu, bool) or not isinstance(mu, int | float) or not lo <= mu <= hi):
        raise InputError(field, mu, f"a friction coefficient in [{lo}, {hi}]")


Friction = Annotated[float, Strict(), Field(ge=FRICTION_RANGE[0], le=FRICTION_RANGE[1], allow_inf_nan=False)]


class PushSettings(StrictModel):
    """One push: ``impulse`` (2 or 3 components, N s, world frame) over ``duration`` s from plan time ``t``."""

    t: Annotated[float, Strict(), Field(ge=0, le=1e4, allow_inf_nan=False)]
    impulse: list[Annotated[float, Strict(), Field(ge=-1000, le=1000, allow_inf_nan=False)]] = Field(
        min_length=2, max_length=3
    )
    duration: Annotated[float, Strict(), Field(gt=0, le=10, allow_inf_nan=False)] = 0.1


class BumpSettings(StrictModel):
    """One bump: a box ``height`` m high from ``x`` to ``x + length`` m along x."""

    x: Annotated[float, Strict(), Field(ge=-1e4, le=1e4, allow_inf_nan=False)]
    height: Annotated[float, Strict(), Field(gt=0, le=0.5, allow_inf_nan=False)]
    length: Annotated[float, Strict(), Field(gt=0, le=10, allow_inf_nan=False)] = 0.2


#: the ``sim:`` keys the planner's driver reads, not the simulator (:meth:`SimSettings.given`)
PLANNER_KEYS = ("terrain", "replan_lead", "footholds")


class SimSettings(StrictModel):
    """Simulation settings of a scenario (module docstring); None = the simulator's default."""

    state: Literal["estimated", "oracle"] | None = None
    noise: Literal["none", "typical", "rl-peer"] | None = None
    noise_scale: (
        Annotated[float, Strict(), Field(ge=NOISE_SCALE_RANGE[0], le=NOISE_SCALE_RANGE[1], allow_inf_nan=False)] | None
    ) = None
    latency: Annotated[int, Strict(), Field(ge=LATENCY_RANGE[0], le=LATENCY_RANGE[1])] | None = None
    friction: Friction | None = None
    assumed_friction: Friction | None = None
    seed: Annotated[int, Strict(), Field(ge=0, le=2**32 - 1)] | None = None
    mass_scale: (
        Annotated[float, Strict(), Field(ge=MASS_SCALE_RANGE[0], le=MASS_SCALE_RANGE[1], allow_inf_nan=False)] | None
    ) = None
    com_offset: (
        list[Annotated[float, Strict(), Field(ge=COM_OFFSET_RANGE[0], le=COM_OFFSET_RANGE[1], allow_inf_nan=False)]]
        | None
    ) = Field(default=None, min_length=3, max_length=3)
    motor_strength: (
        Annotated[float, Strict(), Field(ge=MOTOR_STRENGTH_RANGE[0], le=MOTOR_STRENGTH_RANGE[1], allow_inf_nan=False)]
        | None
    ) = None
    joint_vel_noise: Annotated[float, Strict(), Field(ge=0, le=100, allow_inf_nan=False)] | None = None
    pushes: list[PushSettings] | None = None
    bumps: list[BumpSettings] | None = None
    contact: Literal["force", "torque"] | None = None
    terrain: Literal["known", "blind", "perceived"] | None = None
    replan_lead: Annotated[float, Strict(), Field(ge=0, le=1, allow_inf_nan=False)] | None = None
    footholds: Literal["profile", "plane"] | None = None
    known_floor: Annotated[bool, Strict()] | None = None

    def given(self) -> dict[str, Any]:
        """The keys set in the scenario, as ``SimOptions`` keyword arguments (``pushes`` and ``bumps``
        as lists of plain dicts: the simulator turns them into its own objects); ``terrain``,
        ``replan_lead`` and ``footholds`` are not: the planner's driver reads them
        (:func:`gaitshift.control.drivers.prepare`)."""
        return {k: v for k, v in self.model_dump().items() if v is not None and k not in PLANNER_KEYS}
