"""3D spring-loaded inverted pendulum (3D-SLIP), the running baseline of paper 001 §IV-C.

:mod:`~gaitshift.models.slip.dynamics`: parameters, the flight and stance equations, energy and one
TOF-to-TOF half cycle integrated with events. :mod:`~gaitshift.models.slip.periodic`: the periodic
mirror-symmetric half cycle at a given speed (Levenberg-Marquardt) and the leg calibration to
paper 001 Table I.
"""

from gaitshift.models.slip.dynamics import (
    HalfCycle,
    SlipParams,
    energy,
    flight_rhs,
    leg_direction,
    simulate_half_cycle,
    stance_rhs,
)
from gaitshift.models.slip.periodic import PeriodicGait, calibrate, periodic_half_cycle

__all__ = [
    "HalfCycle",
    "PeriodicGait",
    "SlipParams",
    "calibrate",
    "energy",
    "flight_rhs",
    "leg_direction",
    "periodic_half_cycle",
    "simulate_half_cycle",
    "stance_rhs",
]
