"""Go to a pose: velocity commands from the remaining pose error, and when to stop on the goal.

At every planning instant, with the CoM at ``p`` and the heading ``psi``, the error to the goal
``(x_g, y_g, yaw_g)`` in the heading frame is ``e = R(-psi) (g - p)``, distance ``d = |e|``:

* the speed: the target ramps down by at most ``a tau`` per step (``a`` the per-step acceleration
  limit over the step duration ``tau``) and the CoM reaches a target about :data:`LAG_STEPS` steps
  after it is set (the deadbeat horizon), so from speed ``v`` the robot needs
  ``v^2 / (2 a) + LAG_STEPS tau v`` to stop; the command is the largest ``v`` whose stopping distance
  fits in ``d``: ``v = sqrt((L a)^2 + 2 a d) - L a`` with ``L = LAG_STEPS tau``, capped at ``v_cap``;
* far (``d >`` :data:`NEAR_STEPS` nominal strides): turn toward the goal,
  ``omega = k_psi atan2(e_y, e_x)``, and walk forward at ``v cos(bearing)``;
* near: move holonomically, ``(vx, vy) = v e / d``, and turn to the goal yaw, ``omega = k_psi (yaw_g - psi)``.

The goal is *reached* once the remaining distance fits in the two last steps and the remaining yaw
in their turn limit: the generator then plans one more walking step and the closing ``stop`` step
with the rest point fixed on the goal (:mod:`.planner`), which lands there exactly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from gaitshift.common.rotations import rot2, wrap_angle
from gaitshift.models.arrays import FloatArray
from gaitshift.planners.locomotion.params import LocomotionParams

__all__ = ["Goal", "goto_command"]

#: heading gain, 1/s
K_PSI = 1.5
#: beyond this many nominal strides the robot faces the goal while walking to it
NEAR_STEPS = 3.0
#: largest yaw rate while translating toward a near goal, rad/s
NEAR_YAW_RATE = 0.3
#: steps between a target and the CoM reaching it (the two-step deadbeat horizon)
LAG_STEPS = 2.0


@dataclass(frozen=True)
class Goal:
    """A goal pose: position (2,) m and yaw rad, world frame."""

    xy: FloatArray
    yaw: float


def goto_command(
    goal: Goal, com: FloatArray, heading: float, speed: float, params: LocomotionParams, step_time: float
) -> tuple[FloatArray, bool]:
    """The command (vx, vy, yaw_rate) toward ``goal`` from the CoM ``com`` (2,) and ``heading``, and
    whether the goal can be closed now (two steps left). ``speed`` is the current target speed, m/s;
    ``step_time`` the walking step duration, s."""
    lim = params.limits
    e = rot2(-heading) @ (goal.xy - com)
    d = float(np.hypot(*e))
    yaw_err = wrap_angle(goal.yaw - heading)
    a = lim.max_accel[0] / step_time
    v_cap = 0.9 * params.walk_to_run
    reach = 0.5 * lim.max_stride
    if d <= reach and speed <= lim.max_accel[0] and abs(yaw_err) <= lim.max_turn:
        return np.zeros(3), True
    lag = LAG_STEPS * step_time
    v = min(v_cap, math.sqrt((lag * a) ** 2 + 2.0 * a * d) - lag * a)
    if d > NEAR_STEPS * reach:
        bearing = math.atan2(e[1], e[0])
        omega = K_PSI * bearing
        cmd = np.array([v * max(math.cos(bearing), 0.0), 0.0, omega])
    else:
        u = e / max(d, 1e-9)
        # keep the direction: scale the speed so that no axis exceeds its limit (forward, backward, lateral)
        cap = [lim.max_speed[0] if u[0] >= 0 else lim.max_speed[1], lim.max_speed[2]]
        v = min(v, *(c / max(abs(x), 1e-9) for c, x in zip(cap, u, strict=True)))
        # translate first, turn on the way only slowly: a fast turn rotates the holonomic command in
        # the heading frame from step to step, which the two-step horizon cannot follow
        omega = K_PSI * yaw_err if d <= reach else float(np.clip(K_PSI * yaw_err, -NEAR_YAW_RATE, NEAR_YAW_RATE))
        cmd = np.array([v * u[0], v * u[1], omega])
    return cmd, False
