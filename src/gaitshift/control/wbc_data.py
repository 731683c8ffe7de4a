"""What the whole-body QP takes and gives: its gains, the tick reference and the solve diagnostics.

The gains default to the values tuned on the G1; a robot YAML overrides any of them under its
``control`` key (:func:`gains_for`; docs/robots.md).
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace
from typing import Any

import numpy as np

from gaitshift.errors import InputError


@dataclass(frozen=True)
class Gains:
    """Task weights and PD gains of the whole-body QP (accelerations in m/s^2, rad/s^2 per m, rad, m/s)."""

    com_kp: tuple[float, float, float] = (60.0, 60.0, 300.0)
    com_kd: tuple[float, float, float] = (16.0, 16.0, 35.0)
    w_com: float = 100.0
    w_angmom: float = 10.0
    angmom_kd: float = 10.0
    swing_kp: float = 900.0
    swing_kd: float = 60.0
    w_swing: float = 100.0
    w_swing_rot: float = 3.0
    torso_kp: float = 200.0
    torso_kd: float = 30.0
    w_torso: float = 0.5
    w_pelvis: float = 1.0
    posture_kp: float = 100.0
    posture_kd: float = 20.0
    w_posture: float = 0.002
    w_arm_posture: float = 0.3
    w_reg_qdd: float = 1e-5
    w_reg_f: float = 1e-6
    mu: float = 0.45
    stance_kv: float = 20.0
    torque_margin: float = 0.98
    limit_horizon: float = 0.04  # s; > 0: swing-knee limit avoidance (qdd bounds), 0: off
    limit_margin: float = 0.05  # rad kept from the knee limits


def gains_for(robot: Any, base: Gains | None = None) -> Gains:
    """``base`` (default :class:`Gains`) with the robot config's ``control`` values; the CoM gains
    ``com_kp``/``com_kd`` take one number (horizontal) or are set per axis as ``com_kp_z``/``com_kd_z``.

    Raises:
        InputError: a ``control`` key that is not a gain.
    """
    g = base or Gains()
    names = {f.name for f in fields(Gains)}
    changes: dict[str, Any] = {}
    for key, value in getattr(robot, "control", ()):
        if key in ("com_kp", "com_kd"):
            cur = changes.get(key, getattr(g, key))
            changes[key] = (value, value, cur[2])
        elif key in ("com_kp_z", "com_kd_z"):
            k = key[:-2]
            cur = changes.get(k, getattr(g, k))
            changes[k] = (cur[0], cur[1], value)
        elif key in names:
            changes[key] = float(value)
        else:
            allowed = ", ".join(sorted(names | {"com_kp_z", "com_kd_z"}))
            raise InputError(f"robot.control.{key}", value, f"a gain name ({allowed})")
    return replace(g, **changes)


@dataclass
class TickReference:
    """What the controller tracks at one tick (world frame, SI).

    ``stance``: feet whose contact points carry force and are held still. ``fz_max``: per-foot cap on
    the total normal force, N (force ramp). ``foot_*``: sole-centre references (2, 3); used for feet
    not in stance. ``yaw``: (2,) foot yaws; ``torso_yaw``: heading of pelvis and torso; ``yaw_rate`` (2,)
    and ``torso_yaw_rate``: their rates, rad/s (velocity references of the orientation tasks).
    ``foot_pitch``: (2,) sole inclination on terrain, rad, positive toe up (0 on flat ground): the swing
    sole's reference is ``rot_z(yaw) rot_y(-foot_pitch)``.
    """

    com_pos: np.ndarray
    com_vel: np.ndarray
    com_acc: np.ndarray
    stance: np.ndarray
    fz_max: np.ndarray
    foot_pos: np.ndarray
    foot_vel: np.ndarray
    foot_acc: np.ndarray
    yaw: np.ndarray
    torso_yaw: float = 0.0
    yaw_rate: np.ndarray = field(default_factory=lambda: np.zeros(2))
    torso_yaw_rate: float = 0.0
    foot_pitch: np.ndarray = field(default_factory=lambda: np.zeros(2))

    @classmethod
    def still(
        cls, com_pos: np.ndarray, foot_pos: np.ndarray, stance: tuple[bool, bool] = (True, True), fz_max: float = 1e4
    ) -> TickReference:
        """Hold still: CoM at ``com_pos`` (3,), soles at ``foot_pos`` (2, 3) with yaw 0, zero velocities and
        accelerations; the same normal-force cap ``fz_max`` (N) on both feet."""
        return cls(
            com_pos=np.asarray(com_pos, float),
            com_vel=np.zeros(3),
            com_acc=np.zeros(3),
            stance=np.array(stance),
            fz_max=np.full(2, float(fz_max)),
            foot_pos=np.asarray(foot_pos, float),
            foot_vel=np.zeros((2, 3)),
            foot_acc=np.zeros((2, 3)),
            yaw=np.zeros(2),
        )


@dataclass
class TickInfo:
    """Diagnostics of one solve."""

    ok: bool = True
    solver: str = "daqp"
    forces: np.ndarray = field(default_factory=lambda: np.zeros((2, 3)))
    qdd: np.ndarray | None = None
    contact_wrenches: np.ndarray | None = None  # (6 ns,) [F; tau] per stance sole, about its centre, world frame
    contact_jacobian: np.ndarray | None = None  # (6 ns, nv) the stance soles' frame Jacobians
    stance: tuple[int, ...] = ()  # the stance soles of ``contact_wrenches``, in order (0 left, 1 right)

    def cop_offset(self, side: int) -> np.ndarray | None:
        """Where the solved contact wrench of sole ``side`` puts its centre of pressure, (2,) m, world
        frame, from the sole centre: the point of the sole plane about which the wrench's horizontal
        moment vanishes, ``(-tau_y / F_z, tau_x / F_z)`` for ``[F; tau]`` about the centre (a sole
        plane through its centre, level). None when ``side`` is not a stance sole of this solve or
        carries no load."""
        if self.contact_wrenches is None or side not in self.stance:
            return None
        j = 6 * self.stance.index(side)
        w = self.contact_wrenches[j : j + 6]
        if w[2] <= 0.0:
            return None
        return np.array([-w[4] / w[2], w[3] / w[2]])
