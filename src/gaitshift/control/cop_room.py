"""How far a stance sole can move its centre of pressure: the sole's size and the leg's torques.

The step feedback (:mod:`gaitshift.control.feedback`, ``cop_room``) lets the stance sole take back a
capture-point error with its centre of pressure (CoP). A CoP offset ``r`` along the horizontal axis
``e_x`` (``e_y``) of the sole's heading frame is a moment ``M = F_z r`` about ``e_y`` (``e_x``) at the sole
centre, with ``F_z`` the vertical force the sole carries. The sole bounds it by its half size ``d``;
the leg bounds it by its motors. A wrench ``[F_z e_z; M e]`` at the sole loads the joints between the
sole and the floating base with (statics, ``tau = J^T w``)::

    tau_j = a_j F_z + b_j M,     a_j = (J_lin^T e_z)_j,   b_j = (J_ang^T e)_j = axis_j . e      (1)

(``J`` the sole centre's Jacobian, ``axis_j`` the joint's axis), so ``|tau_j| <= tau_max,j`` allows

    |M| <= min_j (tau_max,j - |a_j| F_z) / |b_j|     over the joints with |b_j| >= 0.1         (2)

and the CoP room is

    r(F_z) = min(d, max(0, M_max(F_z)) / F_z).                                                (3)

A joint turned more than 84 degrees away from ``e`` (``|b_j| < 0.1``) is left out: it barely feels
``M``. The Jacobian is taken at the robot's standing pose, one sole carrying the load. The load over
the time ``tau`` the prediction integrates is the plan's: by the impulse balance of the CoM, the mean
vertical force over ``[t, t + tau]`` is ``m (g + (zd(t + tau) - zd(t)) / tau)`` (``zd`` the plan's
vertical CoM velocity): ``m g`` in a walk, more before a running take-off (:class:`SwingContext`).
On the G1 the motors allow more than the sole at ``m g`` (0.118 / 0.153 m against 0.09 / 0.035 m),
on the T1 less (0.055 / 0.048 m against 0.11 / 0.05 m: its 20 N m ankle pitch motors).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

#: joints whose axis is closer than this to perpendicular to the moment's axis are left out of eq. (2)
MIN_ARM = 0.1


@dataclass(frozen=True)
class CopRoom:
    """Eq. (3) per axis of the sole's heading frame (x: along the sole, y: across).

    Attributes:
        half: (2,) m, the sole's half length and half width ``d``.
        cap: (2, k) N m, ``tau_max,j / |b_j|`` of the joints of eq. (2) per axis (inf where left out).
        slope: (2, k) m, ``|a_j| / |b_j|`` of the same joints.
    """

    half: np.ndarray
    cap: np.ndarray
    slope: np.ndarray

    @classmethod
    def sole_only(cls, half: tuple[float, float]) -> CopRoom:
        """The sole's size alone (motors taken as unlimited)."""
        return cls(np.asarray(half, float), np.full((2, 1), np.inf), np.zeros((2, 1)))

    @classmethod
    def from_plant(cls, plant: Any, data: Any, half: tuple[float, float]) -> CopRoom:
        """Eqs. (1)-(2) for the left sole of ``plant`` (a :class:`~gaitshift.robots.model.RobotModel`)
        in the state of ``data`` (``mj_forward`` done; the standing pose), its motors' limits
        ``plant.torque_limit``; ``half`` (2,) m the plan's sole half sizes."""
        import mujoco

        m = plant.model
        centre, rot = plant.sole_frame(data, 0)
        jp, jr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
        mujoco.mj_jac(m, data, jp, jr, centre, plant.soles[0].body)
        dofs = np.asarray(plant.actuated_dofs)
        heading = rot[:, 0] - rot[2, 0] * np.array([0.0, 0.0, 1.0])
        ex = heading / np.linalg.norm(heading)
        ey = np.cross([0.0, 0.0, 1.0], ex)
        a = np.abs(jp[2, dofs])
        caps, slopes = [], []
        for moment_axis in (ey, ex):  # a CoP shift along x is a moment about y, along y one about x
            b = np.abs(moment_axis @ jr[:, dofs])
            used = b >= MIN_ARM
            caps.append(np.where(used, np.asarray(plant.torque_limit, float) / np.maximum(b, MIN_ARM), np.inf))
            slopes.append(np.where(used, a / np.maximum(b, MIN_ARM), 0.0))
        return cls(np.asarray(half, float), np.array(caps), np.array(slopes))

    def at(self, load: float) -> np.ndarray:
        """Eq. (3): the room (2,) m at the vertical force ``load`` (N, > 0)."""
        moment = np.min(self.cap - self.slope * load, axis=1)
        room: np.ndarray = np.minimum(self.half, np.maximum(moment, 0.0) / load)
        return room
