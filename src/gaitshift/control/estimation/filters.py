"""Registry of the floating-base filters: name -> constructor, each called as ``make(tuning, gravity)``.

``inekf``: point contacts (Hartley 2018); ``inekf-flat``: plus the stance soles' orientations
(Ramadoss 2022); ``leg-odometry``: the baseline.

Both satisfy :class:`gaitshift.control.estimation.types.BaseFilter` (``reset``, ``step``). The default
(``DEFAULT_FILTER``) was chosen by the numbers in docs/estimation.md.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial

from gaitshift.control.estimation.inekf import InvariantEKF
from gaitshift.control.estimation.odometry import LegOdometry
from gaitshift.control.estimation.tuning import FilterTuning
from gaitshift.control.estimation.types import BaseFilter
from gaitshift.errors import check_choice

FILTERS: dict[str, Callable[[FilterTuning, float], BaseFilter]] = {
    "inekf": InvariantEKF,
    "inekf-flat": partial(InvariantEKF, flat_feet=True),
    "leg-odometry": LegOdometry,
}
DEFAULT_FILTER = "inekf-flat"


def make_filter(name: str, tuning: FilterTuning, gravity: float = 9.81) -> BaseFilter:
    """A new filter of that name.

    Raises:
        InputError: unknown name.
    """
    check_choice("estimator.filter", name, FILTERS)
    return FILTERS[name](tuning, gravity)
