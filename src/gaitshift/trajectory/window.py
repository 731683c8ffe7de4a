"""A window of a plan: the samples of a run from one instant on, indexed by absolute time.

A live plan (:mod:`gaitshift.control.locomotion_driver`) grows with the run: a 10-minute run at 500 Hz
holds 300 000 samples. The closed loop needs only the samples from a little before now to the end of its
look-ahead, so a live plan is handed over as a **window**: a :class:`~gaitshift.trajectory.contract.Trajectory`
whose first sample is not the run's first. Its times stay absolute (``t[0] = first * dt``), so the sample
at time ``t`` is

.. math::

    i(t) = \\operatorname{clip}\\left(\\operatorname{round}(t / dt) - \\mathrm{first},\\ 0,\\ N - 1\\right),
    \\qquad \\mathrm{first} = \\operatorname{round}(t_0 / dt)                                       (1)

A plan that starts at t = 0 (every planner's whole plan) is the window with ``first = 0``, so (1) is the
one way to index any plan by time. :func:`window` cuts one out of a plan; :func:`join` puts consecutive
pieces (:func:`cut`) of a run back into one plan (the run's plan as the loop tracked it,
:class:`gaitshift.control.plan_history.PlanHistory`).

Per-sample arrays (the contract's and the extras of length N) are cut; the footholds (per foothold) and
the meta are kept whole; the extra ``boundary_t`` (phase boundary times, s) keeps the boundaries that
fall inside the window.
"""

from __future__ import annotations

import numpy as np

from gaitshift.trajectory.contract import SAMPLE_KEYS, Trajectory

__all__ = ["cut", "first_index", "index_at", "join", "window"]

#: extras indexed by something else than the sample (kept whole, or cut by time)
_BOUNDARIES = "boundary_t"


def first_index(traj: Trajectory) -> int:
    """The run's sample number of ``traj``'s first sample (0 for a plan that starts at t = 0)."""
    return round(float(traj.t[0]) / traj.dt)


def index_at(traj: Trajectory, t: float) -> int:
    """The sample of ``traj`` at time ``t`` s, eq. (1): the first or the last sample outside it."""
    return min(max(round(t / traj.dt) - first_index(traj), 0), len(traj) - 1)


def _per_sample(traj: Trajectory) -> list[str]:
    n = len(traj)
    extra = [k for k, v in traj.extras.items() if k != _BOUNDARIES and np.ndim(v) >= 1 and len(v) == n]
    return [*SAMPLE_KEYS, *extra]


def cut(traj: Trajectory, start: int, stop: int | None = None) -> dict[str, np.ndarray]:
    """Copies of ``traj``'s per-sample arrays from the run's sample ``start`` up to (not including) ``stop``
    (None: the end; any number of samples, none included), and its ``boundary_t`` in that time span."""
    first = first_index(traj)
    i0 = min(max(start - first, 0), len(traj))
    i1 = len(traj) if stop is None else min(max(stop - first, i0), len(traj))
    keys = _per_sample(traj)
    out = {k: np.array(v[i0:i1]) for k, v in traj.arrays().items() if k in keys}
    bt = traj.extras.get(_BOUNDARIES)
    if bt is not None:
        lo, hi = (first + i0 - 0.5) * traj.dt, (first + i1 - 0.5) * traj.dt
        out[_BOUNDARIES] = bt[(bt > lo) & (bt < hi)].copy()
    return out


def _whole(data: dict[str, np.ndarray], like: Trajectory) -> Trajectory:
    """The cut ``data`` as a plan with ``like``'s footholds, other extras and meta."""
    rest = {k: v for k, v in like.arrays().items() if k not in _per_sample(like) and k != _BOUNDARIES}
    return Trajectory.from_arrays(rest | data, like.meta)


def window(traj: Trajectory, start: int, stop: int | None = None) -> Trajectory:
    """The samples of ``traj`` from the run's sample ``start`` up to (not including) ``stop`` (None: the
    end) as a plan (at least two samples: the window is widened backwards when needed)."""
    first = first_index(traj)
    end = len(traj) + first if stop is None else min(max(stop, first + 2), len(traj) + first)
    return _whole(cut(traj, min(start, end - 2), end), traj)


def join(cuts: list[dict[str, np.ndarray]], last: Trajectory, start: int) -> Trajectory:
    """One run's plan from consecutive :func:`cut` pieces (each from the sample after the last one's end)
    and the plan ``last`` from the run's sample ``start`` on: per-sample arrays and ``boundary_t`` end to
    end, the footholds and the meta of ``last`` (a live plan's footholds only grow)."""
    pieces = [*cuts, cut(last, start)]
    data = {k: np.concatenate([p[k] for p in pieces]) for k in pieces[-1] if k != _BOUNDARIES}
    if all(_BOUNDARIES in p for p in pieces):
        data[_BOUNDARIES] = np.concatenate([p[_BOUNDARIES] for p in pieces])
    return _whole(data, last)
