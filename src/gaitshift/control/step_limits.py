"""Kinematic limits of a re-chosen foothold: the leg's reach from its hip, and no crossing of the feet.

A foothold ``p`` of leg ``s`` (horizontal, m) chosen by the step adjustment
(:mod:`gaitshift.control.feedback`) is kept where the leg can put it at touchdown:

* **reach**: inside the disc of radius ``r`` around the hip's ground projection at touchdown,

  .. math:: r = \\sqrt{(\\rho L)^2 - z_{hip}^2},\\qquad z_{hip} = h - (h_0 - z_{hip,0}),          (1)

  with ``L`` the robot's leg length (hip-pitch axis to sole, leg straight: ``RobotConfig.leg_length``),
  ``rho`` < 1 the share of it the knee may straighten to (``CaptureSettings.reach_fraction``: a
  straight knee is a singularity), ``h`` the plan's CoM height, and ``h_0`` / ``z_{hip,0}`` the CoM
  and hip-pitch-axis heights above the soles in the robot's standing pose (the hip sits
  ``h_0 - z_{hip,0}`` below the CoM). The hip at touchdown is predicted to first order from the
  measured CoM, ``c + T cd`` (``T`` the time left to the planned touchdown), plus the hip's lateral
  offset ``+-w_hip`` from the CoM in the standing pose, turned by the heading yaw;
* **no crossing**: in the heading frame, the lateral distance ``l`` of the foothold from the other foot
  (on the ground: measured; swinging: its own adjusted foothold), counted positive on the foot's own
  side (left foot to the left), is at least

  .. math:: l_{min}(a) = w \\max\\left(\\operatorname{clip}\\left(\\frac{L + c - |a|}{c}, 0, 1\\right),
            \\operatorname{clip}\\left(\\frac{|a| - 2L - c}{c}, 0, 1\\right)\\right),          (2)

  with ``a`` the distance of the two sole centres along the heading, ``L`` x ``w`` the sole size and
  ``c`` a clearance (``CaptureSettings.tandem_clearance``): the full sole width ``w`` between the
  centres, except where the foot lands a short step ahead of (or behind) the other one,
  ``L + c <= |a| <= 2L + c`` (its toe at least ``c`` short of the other heel, and at most one more
  sole length beyond it); there it may land in line with the other foot (a tandem step, ``l = 0``),
  never across it. The ramps of width ``c`` keep the bound continuous, so a foothold re-targeted
  mid-swing moves continuously. A tandem step is what catches a push toward the stance foot while
  running: the swinging foot cannot land under a capture point beyond the stance sole, but the stance
  foot lifts off before the other lands, and a stride ahead the swing foot can land on its line; the
  other foot's next swing then passes it on the outside. Why short steps only: the other leg's next
  swing passes the lined-up foot, and on a long stride it swings through with its knee well ahead of
  its foot, so it passes the stance leg before its foot has moved out. Measured on the G1
  (docs/simulation.md, "Pushes while running"): lined up at ``|a|`` = 0.22-0.24 m (0.2 m stride) the
  legs never touched up to 27 N s pushes; lined up at ``|a|`` = 0.56-0.78 m (2.05 m/s, 0.82 m stride)
  they touched and the robot fell. The upper end ``2L + c`` (0.37 m on the G1) is a choice between
  the two, not a derived bound. With ``c`` None the bound is ``w`` everywhere (the guard before
  tandem steps).

Every number comes from the robot's model and YAML (:meth:`StepLimits.from_plant`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from gaitshift.robots.dimensions import standing_data

__all__ = ["StepLimits"]


@dataclass(frozen=True)
class StepLimits:
    """Reach and crossing limits of one run (module docstring).

    Attributes:
        reach: r of eq. (1), m (horizontal, hip to sole centre).
        hip_offset: lateral distance from the CoM to each hip-pitch axis when standing, m.
        min_width: smallest lateral distance between the two sole centres side by side (the sole
            width w), m.
        sole_length: the sole length L of eq. (2), m (inf: the feet never line up).
        clearance: c of eq. (2), m (> 0).
    """

    reach: float
    hip_offset: float
    min_width: float
    sole_length: float = math.inf
    clearance: float = 0.0

    @classmethod
    def from_plant(cls, plant: Any, height: float, reach_fraction: float, clearance: float | None = None) -> StepLimits:
        """The limits of ``plant`` (a :class:`gaitshift.sim.plant.Plant`; its robot config and model in
        the standing pose) for a plan of CoM height ``height`` (m), eq. (1), and the toe-to-heel
        ``clearance`` (m) of eq. (2) (None: the feet never line up)."""
        robot, m = plant.robot, plant.model
        d, _ = standing_data(m, robot.standing_pose)
        hips = np.array([d.xanchor[m.joint(h).id] for h in robot.hips])
        com = d.subtree_com[0]
        z_hip = float(height) - (float(com[2]) - float(hips[:, 2].mean()))
        leg = reach_fraction * float(robot.leg_length)
        reach = math.sqrt(max(leg**2 - max(z_hip, 0.0) ** 2, 0.0))
        return cls(
            reach=reach,
            hip_offset=float(np.abs(hips[:, 1] - com[1]).mean()),
            min_width=float(robot.sole_size[1]),
            sole_length=math.inf if clearance is None else float(robot.sole_size[0]),
            clearance=0.0 if clearance is None else float(clearance),
        )

    def min_gap(self, along: float) -> float:
        """l_min of eq. (2), m, for sole centres ``along`` m apart along the heading."""
        if not math.isfinite(self.sole_length):
            return self.min_width
        c, a, length = max(self.clearance, 1e-9), abs(along), self.sole_length
        apart = min(max((length + c - a) / c, 0.0), 1.0)
        long = min(max((a - 2.0 * length - c) / c, 0.0), 1.0)
        return self.min_width * max(apart, long)

    def clamp(self, side: int, foothold: np.ndarray, hip_com: np.ndarray, yaw: float, other: np.ndarray) -> np.ndarray:
        """``foothold`` (3,) m of leg ``side`` (0 left, 1 right) moved into the reach disc around the
        predicted CoM ``hip_com`` (3,) m plus the hip offset, then out of the other foot's side of
        ``other`` (3,) m by eq. (2) (module docstring); z untouched."""
        c, s_ = math.cos(yaw), math.sin(yaw)
        forward, lateral = np.array([c, s_]), np.array([-s_, c])
        sign = 1.0 if side == 0 else -1.0
        hip = np.asarray(hip_com, float)[:2] + sign * self.hip_offset * lateral
        out = np.array(foothold, float)
        rel = out[:2] - hip
        dist = float(np.linalg.norm(rel))
        if dist > self.reach:
            out[:2] = hip + rel * (self.reach / dist)
        rel_other = out[:2] - np.asarray(other, float)[:2]
        gap, need = sign * float(lateral @ rel_other), self.min_gap(float(forward @ rel_other))
        if gap < need:
            out[:2] += sign * (need - gap) * lateral
        return out
