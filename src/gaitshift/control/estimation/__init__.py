"""State estimation: what the controller knows when it sees only what the robot senses.

Public API::

    from gaitshift.control.estimation import StateEstimator, ImuReading, JointReading, FootForces
    est = StateEstimator.from_robot(load_robot("g1"), dt=0.002, noise="typical")   # filter="inekf"
    est.reset(qpos0, qvel0)
    state = est.step(ImuReading(gyro, accel), JointReading(q, qd), FootForces(normal))  # EstimatedState

The pieces (each usable alone): :class:`ContactDetector`, :class:`JointVelocityFilter`,
:class:`LegKinematics`, the base filters :class:`InvariantEKF` and :class:`LegOdometry` (registry
:data:`FILTERS`) and the noise profiles :data:`PROFILES` (the world's corrupter:
:class:`gaitshift.sim.sensor_noise.SensorNoise`). The test and
benchmark inputs (a synthetic walk with analytic truth, a recorded G1 sway) live in
:mod:`gaitshift.bench`. Equations and measured numbers: docs/estimation.md.
"""

from gaitshift.control.estimation.calibration import GyroCalibration
from gaitshift.control.estimation.contact import ContactDetector
from gaitshift.control.estimation.estimator import StateEstimator
from gaitshift.control.estimation.filters import DEFAULT_FILTER, FILTERS, make_filter
from gaitshift.control.estimation.inekf import InvariantEKF
from gaitshift.control.estimation.joints import JointVelocityFilter
from gaitshift.control.estimation.kinematics import BodyKinematics, LegKinematics
from gaitshift.control.estimation.noise import PROFILES, Channel, NoiseProfile, noise_profile
from gaitshift.control.estimation.odometry import LegOdometry
from gaitshift.control.estimation.tuning import FilterTuning
from gaitshift.control.estimation.types import (
    BaseFilter,
    BaseState,
    EstimatedState,
    FootForces,
    FootKinematics,
    ImuReading,
    JointReading,
)

__all__ = [
    "DEFAULT_FILTER",
    "FILTERS",
    "PROFILES",
    "BaseFilter",
    "BaseState",
    "BodyKinematics",
    "Channel",
    "ContactDetector",
    "EstimatedState",
    "FilterTuning",
    "FootForces",
    "FootKinematics",
    "GyroCalibration",
    "ImuReading",
    "InvariantEKF",
    "JointReading",
    "JointVelocityFilter",
    "LegKinematics",
    "LegOdometry",
    "NoiseProfile",
    "StateEstimator",
    "make_filter",
    "noise_profile",
]
