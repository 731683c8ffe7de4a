"""External pushes on the pelvis: their definition, placement at mid-stance, and the per-tick force."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from gaitshift.common.runs import true_runs
from gaitshift.trajectory.contract import SS, Trajectory


@dataclass(frozen=True)
class Push:
    """A horizontal force applied to the pelvis for ``duration`` s from plan time ``t`` (s).

    ``impulse`` (N s) along ``direction`` (unit (2,) in the ground plane)."""

    t: float
    impulse: float
    duration: float = 0.1
    direction: tuple[float, float] = (0.0, 1.0)


def mid_stance_pushes(
    traj: Trajectory, impulse: float, steps: tuple[int, ...] = (4, 8), duration: float = 0.1
) -> tuple[Push, ...]:
    """Lateral pushes of ``impulse`` N s centred at mid single support of the given (1-based) steps,
    alternating +y, -y. Steps beyond the plan are ignored."""
    ss = true_runs(traj.phase == SS)
    out = []
    for j, k in enumerate(steps):
        if 1 <= k <= len(ss):
            s, e = ss[k - 1]
            tm = 0.5 * (traj.t[s] + traj.t[min(e, len(traj) - 1)])
            out.append(
                Push(
                    t=float(tm - duration / 2),
                    impulse=float(impulse),
                    duration=duration,
                    direction=(0.0, 1.0 if j % 2 == 0 else -1.0),
                )
            )
    return tuple(out)


def push_forces(pushes: tuple[Push, ...], settle: float, dt: float, n_ticks: int) -> np.ndarray:
    """World force on the pelvis at each control tick, (n_ticks, 3) N.

    A push covers ``max(1, round(duration / dt))`` ticks from tick ``round((t + settle) / dt)`` with
    the constant force ``impulse / (ticks dt)``, so that its impulse is exact on the tick grid.
    """
    force = np.zeros((n_ticks, 3))
    for p in pushes:
        i0 = round((p.t + settle) / dt)
        i1 = i0 + max(1, round(p.duration / dt))
        dirn = np.array([*p.direction, 0.0])
        dirn /= max(np.linalg.norm(dirn), 1e-12)
        force[i0 : min(i1, n_ticks)] = dirn * p.impulse / ((i1 - i0) * dt)
    return force
