"""The few numbers of a robot that scenarios default from (read from its model by
:mod:`gaitshift.robots`), so that planners get plain numbers and never load a model."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["RobotFacts"]


@dataclass(frozen=True)
class RobotFacts:
    """Facts of one robot, SI units.

    Attributes:
        name: robot name.
        mass: total mass, kg.
        com_height: CoM height above the soles in the standing pose, m.
        leg_length: hip-pitch axis to sole centre with the leg straight, m.
        sole_size: sole (length, width), m.
        foot_separation: lateral distance between the sole centres when standing, m.
    """

    name: str
    mass: float
    com_height: float
    leg_length: float
    sole_size: tuple[float, float]
    foot_separation: float
