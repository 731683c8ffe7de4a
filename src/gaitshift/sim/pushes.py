"""External pushes on the pelvis: their definition, placement at mid-stance, the CLI form, and the
per-tick force.

A push is an impulse ``J`` (N s, a vector) spread as a constant force ``J / T`` over ``T`` s from plan
time ``t``. On the command line (``gaitshift simulate --push``) a push is either

* ``J``: one number, the legacy form: lateral impulses of ``J`` N s at mid single support of steps 4
  (+y) and 8 (-y) (:func:`mid_stance_pushes`); or
* ``T,JX,JY[,JZ[,DURATION]]``: an impulse (JX, JY, JZ) N s in the world frame from plan time ``T`` s,
  over ``DURATION`` s (default :data:`DEFAULT_DURATION`); repeat the flag for several pushes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from gaitshift.common.runs import true_runs
from gaitshift.errors import InputError
from gaitshift.trajectory.contract import SS, Trajectory

#: default push duration, s
DEFAULT_DURATION = 0.1
#: largest impulse magnitude accepted, N s, and the longest push, s
MAX_IMPULSE = 1000.0
MAX_DURATION = 10.0

#: unit directions of the mid-stance push patterns: one per push, cycled (``lateral`` alternates sides)
PATTERNS: dict[str, tuple[tuple[float, float], ...]] = {
    "lateral": ((0.0, 1.0), (0.0, -1.0)),
    "forward": ((1.0, 0.0),),
    "backward": ((-1.0, 0.0),),
}


@dataclass(frozen=True)
class Push:
    """A force applied to the pelvis for ``duration`` s from plan time ``t`` (s).

    ``impulse`` (N s) along ``direction`` ((2,) in the ground plane, or (3,) with a vertical part;
    normalised when the force is built)."""

    t: float
    impulse: float
    duration: float = DEFAULT_DURATION
    direction: tuple[float, ...] = (0.0, 1.0)


def mid_stance_pushes(
    traj: Trajectory,
    impulse: float,
    steps: tuple[int, ...] = (4, 8),
    duration: float = DEFAULT_DURATION,
    pattern: str = "lateral",
) -> tuple[Push, ...]:
    """Pushes of ``impulse`` N s centred at mid single support of the given (1-based) steps, with the
    directions of :data:`PATTERNS` ``pattern`` in turn (``lateral``: +y, -y, ...). Steps beyond the
    plan are ignored."""
    dirs = PATTERNS[pattern]
    ss = true_runs(traj.phase == SS)
    out = []
    for j, k in enumerate(steps):
        if 1 <= k <= len(ss):
            s, e = ss[k - 1]
            tm = 0.5 * (traj.t[s] + traj.t[min(e, len(traj) - 1)])
            out.append(
                Push(
                    t=float(tm - duration / 2), impulse=float(impulse), duration=duration, direction=dirs[j % len(dirs)]
                )
            )
    return tuple(out)


def parse_push(text: str, flag: str = "--push") -> Push | float:
    """A ``--push`` value (module docstring): a :class:`Push`, or the legacy impulse (float, N s).

    Raises:
        InputError: not one number >= 0, nor 3 to 5 comma-separated finite numbers with ``T`` >= 0,
            ``DURATION`` in (0, :data:`MAX_DURATION`] and ``|J|`` <= :data:`MAX_IMPULSE`.
    """
    allowed = (
        f"J (N s >= 0: lateral pushes at steps 4 and 8) or T,JX,JY[,JZ[,DURATION]]"
        f" (T >= 0 s, |J| <= {MAX_IMPULSE:g} N s, 0 < DURATION <= {MAX_DURATION:g} s)"
    )
    try:
        vals = [float(v) for v in text.split(",")]
    except ValueError:
        raise InputError(flag, text, allowed) from None
    if not vals or not all(math.isfinite(v) for v in vals):
        raise InputError(flag, text, allowed)
    if len(vals) == 1:
        if not 0.0 <= vals[0] <= MAX_IMPULSE:
            raise InputError(flag, text, allowed)
        return vals[0]
    if not 3 <= len(vals) <= 5:
        raise InputError(flag, text, allowed)
    t, j = vals[0], np.array([*vals[1:4], 0.0][:3])
    dur = vals[4] if len(vals) == 5 else DEFAULT_DURATION
    mag = float(np.linalg.norm(j))
    if t < 0 or not 0 < dur <= MAX_DURATION or mag > MAX_IMPULSE:
        raise InputError(flag, text, allowed)
    direction = tuple(float(v) for v in (j / mag if mag > 0 else np.array([0.0, 1.0, 0.0])))
    return Push(t=t, impulse=mag, duration=dur, direction=direction)


def push_forces(pushes: tuple[Push, ...], settle: float, dt: float, n_ticks: int) -> np.ndarray:
    """World force on the pelvis at each control tick, (n_ticks, 3) N.

    A push covers ``max(1, round(duration / dt))`` ticks from tick ``round((t + settle) / dt)`` with
    the constant force ``impulse / (ticks dt)``, so that its impulse is exact on the tick grid.
    Overlapping pushes add.
    """
    force = np.zeros((n_ticks, 3))
    for p in pushes:
        i0 = round((p.t + settle) / dt)
        i1 = i0 + max(1, round(p.duration / dt))
        dirn = np.zeros(3)
        dirn[: len(p.direction)] = p.direction
        dirn /= max(float(np.linalg.norm(dirn)), 1e-12)
        force[i0 : min(i1, n_ticks)] += dirn * p.impulse / ((i1 - i0) * dt)
    return force
