"""What the controller needs to know about the robot it drives: a structural interface.

The controller (``gaitshift.control``) sits below the simulation (``gaitshift.sim``) in the layer
order, so it cannot import the simulated plant. It states here the attributes it reads; the plant of
the simulation (:class:`gaitshift.sim.plant.Plant`) has them, and so can any other model.
"""

from __future__ import annotations

from typing import Any, Protocol

import numpy as np


class SoleView(Protocol):
    """One sole: on body ``body``, its centre ``centre`` (3,) m and frame ``rotation`` (3, 3) in the body
    frame, contact ``points`` (n, 3) m in the sole frame relative to its centre."""

    @property
    def body(self) -> int: ...

    @property
    def centre(self) -> np.ndarray: ...

    @property
    def rotation(self) -> np.ndarray: ...

    @property
    def points(self) -> np.ndarray: ...


class PlantView(Protocol):
    """A compiled MuJoCo model with torque motors and the indices the controller needs.

    ``model`` (MjModel), ``soles`` (left, right), ``torque_limit`` (nu,) N m, ``actuated_dofs`` (nu,)
    dof index of each motor, ``torso_body`` / ``pelvis_body`` (the floating base) body ids, ``mass`` kg.
    """

    @property
    def model(self) -> Any: ...

    @property
    def soles(self) -> tuple[SoleView, SoleView]: ...

    @property
    def torque_limit(self) -> np.ndarray: ...

    @property
    def actuated_dofs(self) -> np.ndarray: ...

    @property
    def torso_body(self) -> int: ...

    @property
    def pelvis_body(self) -> int: ...

    @property
    def mass(self) -> float: ...

    @property
    def robot(self) -> Any:
        """The robot config (:class:`gaitshift.robots.config.RobotConfig`): joint names (``knees``,
        ``arm_joints``)."""
        ...

    def sole_frame(self, data: Any, side: int) -> tuple[np.ndarray, np.ndarray]:
        """Sole centre (3,) m and sole frame rotation (3, 3) of foot ``side`` (0 left, 1 right)."""
        ...
