"""The controller's settings: everything the robot's computer is configured with, in one frozen object."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from typing import Any

from gaitshift.control.estimation.filters import FILTERS
from gaitshift.control.feedback import CaptureSettings
from gaitshift.control.position_filter import POSITION_TAU_RANGE
from gaitshift.control.reference import SwingSettings
from gaitshift.control.replanner import REPLAN_MODES
from gaitshift.control.schedule import ScheduleSettings
from gaitshift.control.wbc_data import Gains
from gaitshift.errors import InputError, check_choice, number_in
from gaitshift.scenario.sim_settings import (
    CONTACT_SOURCES,
    LATENCY_RANGE,
    NOISE_PROFILES,
    NOISE_SCALE_RANGE,
    STATE_SOURCES,
    check_friction,
)

__all__ = ["CONTACT_SOURCES", "STANCE_POINTS", "ControllerSettings", "contact_source"]

#: the points of a stance sole the estimator may take as still (:attr:`ControllerSettings.stance_point`)
STANCE_POINTS = ("cop", "centre")


@dataclass(frozen=True)
class ControllerSettings:
    """How the controller is configured.

    Attributes:
        gains: whole-body QP weights and gains; None: the defaults with the robot YAML's ``control``
            values (:func:`gaitshift.control.wbc_data.gains_for`).
        schedule: foot state machine timing; capture: step feedback; swing: swing-path additions.
        settle: s of standing before the plan starts.
        state: what the controller acts on, "estimated" (its estimator) or "oracle" (the frame's
            :class:`~gaitshift.control.frames.OracleState`); None: "estimated" (every robot has an IMU,
            its YAML's ``sensors.imu``).
        noise, noise_scale: the sensor noise profile the estimator is tuned to, and its factor.
        estimator: base filter of the state estimator (:data:`~gaitshift.control.estimation.filters.FILTERS`).
        assumed_friction: the friction assumed at start (None: the conservative default).
        latency: ticks between a frame and its command acting on the robot, compensated by prediction
            (:mod:`gaitshift.control.state`, eq. (1)); 0: none.
        contact: the contact detector's sole forces: ``"force"`` (the robot's foot-force sensors) or
            ``"torque"`` (from the motors' torques, :mod:`gaitshift.control.estimation.torque_contact`);
            None: what the robot has (:func:`contact_source`).
        replan: where a plan driver re-plans (:mod:`gaitshift.control.replanner`): ``"inline"`` (in the
            tick: deterministic), ``"thread"`` or ``"process"`` (a background worker; the tick never waits
            for a re-plan, the new plan is tracked from the tick that finds it done).
        floor: the height, m, of a flat floor the controller knows the robot stands on (the height of a
            flat stance sole is then a measurement of its estimator,
            :mod:`~gaitshift.control.estimation.floor`); None: no such floor is known.
        position_tau: s, the time constant of the horizontal base position the controller acts on: the
            estimate's velocity integrated and pulled to its position (:mod:`~gaitshift.control.position_filter`,
            eq. (1)); 0: the estimate's position, kicked by its corrections. The G1's 10-minute soak in one
            process, seed 0 / 1: falls at 141.5 / 112.7 s with 0, at 200.9 / 409.6 s with 2 s, at 289.4 s
            (seed 0) with 5 s; holds to its end with 20 s (seeds 0-2; with a tick of latency, one seed of
            three, and three of four with the stance point at the CoP: docs/deploy.md, "The estimate's position,
            kicked by its corrections" and "The stance point at the centre of pressure").
        stance_point: the point of a stance sole the estimator takes as still, with contact from the
            torques: ``"cop"`` (its centre of pressure, eq. (4) of
            :mod:`~gaitshift.control.estimation.torque_contact`) or ``"centre"`` (the sole's centre); a CoP
            too noisy for the sensors (``rl-peer`` encoders) keeps the centre
            (:data:`gaitshift.control.state.COP_STD_MAX`); docs/deploy.md, "The stance point at the centre
            of pressure".
    """

    gains: Gains | None = None
    schedule: ScheduleSettings = field(default_factory=ScheduleSettings)
    capture: CaptureSettings = field(default_factory=CaptureSettings)
    swing: SwingSettings = field(default_factory=SwingSettings)
    settle: float = 0.0
    state: str | None = None
    noise: str = "typical"
    noise_scale: float = 1.0
    estimator: str = "inekf"
    assumed_friction: float | None = None
    latency: int = 0
    contact: str | None = None
    replan: str = "inline"
    floor: float | None = None
    position_tau: float = 20.0
    stance_point: str = "cop"

    def __post_init__(self) -> None:
        if self.state is not None:
            check_choice("state", self.state, STATE_SOURCES)
        check_choice("noise", self.noise, NOISE_PROFILES)
        number_in("noise_scale", self.noise_scale, NOISE_SCALE_RANGE)
        number_in("settle", self.settle, (0.0, 60.0), " s")
        check_friction("assumed_friction", self.assumed_friction)
        if self.contact is not None:
            check_choice("contact", self.contact, CONTACT_SOURCES)
        check_choice("estimator", self.estimator, FILTERS)
        lat = self.latency
        if isinstance(lat, bool) or not isinstance(lat, int) or not LATENCY_RANGE[0] <= lat <= LATENCY_RANGE[1]:
            raise InputError("latency", lat, f"an integer number of ticks in [{LATENCY_RANGE[0]}, {LATENCY_RANGE[1]}]")
        if self.floor is not None and not (isinstance(self.floor, (int, float)) and math.isfinite(self.floor)):
            raise InputError("floor", self.floor, "a finite height, m, or None")
        check_choice("replan", self.replan, REPLAN_MODES)
        number_in("position_tau", self.position_tau, POSITION_TAU_RANGE, "s")
        check_choice("stance_point", self.stance_point, STANCE_POINTS)

    @classmethod
    def of(cls, **given: Any) -> ControllerSettings:
        """Settings from keyword values; an unknown key is an :class:`InputError` naming it."""
        names = [f.name for f in fields(cls)]
        for key in given:
            check_choice("settings", key, names)
        return cls(**given)


def floor_height(known: bool, flat: bool, bumps: Any) -> float | None:
    """:attr:`ControllerSettings.floor` of a world: 0 (the floor's height) when the controller is told
    (``known``) that a world without terrain (``flat``) and without ``bumps`` is the flat floor, else None."""
    return 0.0 if known and flat and not bumps else None


def contact_source(contact: str | None, robot: Any) -> str:
    """Where contact sensing comes from: ``contact`` when given, else ``"force"`` for a robot whose soles
    measure force and ``"torque"`` for one whose do not (``sensors.foot_force`` of the robot YAML,
    :class:`gaitshift.robots.sensors.RobotSensors`; ``robot`` a :class:`gaitshift.robots.RobotConfig`)."""
    return contact if contact is not None else str(robot.sensors.contact)
