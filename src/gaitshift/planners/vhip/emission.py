"""The plan buffer of a streaming CoM generator and the samples emitted from it.

Layout (:data:`PLAN_FIELDS`): per planned sample the horizontal CoM ``c`` (2,) m, the vertical CoM
``z`` m, ``zd`` m/s, ``zdd`` m/s^2, the horizontal ZMP ``zmp`` (2,) m (NaN where no force acts), the
contact ``phase`` (int8) and ``contact`` (2,) bool. The horizontal CoM is planned on the sample grid
(eqs. (7)-(9) of paper 003: a tridiagonal solve per step), the vertical one analytically.

Emitted samples (:func:`emit_samples`, see docs/vhip.md, "What exact means"): ``com_acc`` is the second
difference ``(c_{i+1} - 2 c_i + c_{i-1}) / dt^2`` and ``com_vel`` the central difference
``(c_{i+1} - c_{i-1}) / (2 dt)``, so the discrete dynamics hold at every sample to rounding; a
force-free sample (``z'' + g`` at most ``force_eps g``) has zero horizontal acceleration; the vertical
values are the planned ones; ``stiffness`` is ``sqrt(z / (z'' + g))`` in support.
"""

from __future__ import annotations

import numpy as np

from gaitshift.models.arrays import BoolArray, FloatArray, Int8Array
from gaitshift.planners.streaming.buffer import SampleBuffer
from gaitshift.planners.streaming.samples import Samples
from gaitshift.planners.vhip.swings import FootTracks
from gaitshift.trajectory.contract import DS, FLIGHT, LEFT, RIGHT, SS

__all__ = ["PLAN_FIELDS", "contact_of", "emit_samples", "hold_at_rest", "plan_buffer", "write_segment"]

#: column -> (per-sample shape, dtype) of the plan buffer
PLAN_FIELDS: dict[str, tuple[tuple[int, ...], type[np.generic]]] = {
    "c": ((2,), np.float64),
    "z": ((), np.float64),
    "zd": ((), np.float64),
    "zdd": ((), np.float64),
    "zmp": ((2,), np.float64),
    "phase": ((), np.int8),
    "contact": ((2,), np.bool_),
}


def plan_buffer(capacity: int = 4096) -> SampleBuffer:
    """An empty plan buffer (:data:`PLAN_FIELDS`)."""
    return SampleBuffer(PLAN_FIELDS, capacity)


def contact_of(phase: Int8Array, side: int) -> BoolArray:
    """Contact flags (m, 2) of a segment whose single supports stand on ``side``: both feet in double
    support, ``side`` in single support, none in flight."""
    contact = np.zeros((len(phase), 2), dtype=bool)
    contact[phase == DS] = True
    contact[phase == SS, side] = True
    return contact


def write_segment(
    buf: SampleBuffer,
    start: int,
    c: FloatArray,
    z3: tuple[FloatArray, FloatArray, FloatArray],
    zmp: FloatArray,
    phase: Int8Array,
    contact: BoolArray,
) -> None:
    """Write a planned segment from global index ``start``: horizontal CoM (m, 2), vertical
    ``(z, zd, zdd)`` (m,) each, ZMP (m, 2), phase (m,), contact (m, 2)."""
    buf.write(start, c=c, z=z3[0], zd=z3[1], zdd=z3[2], zmp=zmp, phase=phase, contact=contact)


def hold_at_rest(buf: SampleBuffer, upto: int, zmp: FloatArray) -> None:
    """Extend the plan with standing samples up to index ``upto``: the last CoM at rest, both feet
    down, the ZMP at ``zmp`` (2,)."""
    if buf.n > upto:
        return
    m = upto - buf.n + 1
    last = buf.n - 1
    buf.write(
        buf.n,
        c=np.repeat(buf["c"][last][None], m, 0),
        z=np.full(m, buf["z"][last]),
        zd=np.zeros(m),
        zdd=np.zeros(m),
        zmp=np.repeat(zmp[None], m, 0),
        phase=np.full(m, DS, np.int8),
        contact=np.ones((m, 2), bool),
    )


def emit_samples(
    buf: SampleBuffer,
    feet: FootTracks,
    i: int,
    m: int,
    dt: float,
    g: float,
    command: FloatArray,
    force_eps: float,
) -> Samples:
    """Samples i..i+m-1 of the plan (sample i+m must be planned: the central differences need it).

    ``command`` (2,) m/s is the command in force; ``force_eps`` the relative vertical force below
    which a sample is force-free (its horizontal acceleration is then 0)."""
    sl = slice(i, i + m)
    col = buf["c"]
    cc = col[i - 1 : i + m + 1] if i > 0 else np.concatenate([col[0:1], col[0 : m + 1]])
    pos, vel, acc = np.empty((m, 3)), np.empty((m, 3)), np.empty((m, 3))
    pos[:, :2] = cc[1:-1]
    np.subtract(cc[2:], cc[:-2], out=vel[:, :2])
    vel[:, :2] *= 0.5 / dt
    acc[:, :2] = (cc[2:] - 2.0 * cc[1:-1] + cc[:-2]) * (1.0 / (dt * dt))
    z, zdd = buf["z"][sl], buf["zdd"][sl]
    pos[:, 2], vel[:, 2], acc[:, 2] = z, buf["zd"][sl], zdd
    phase = buf["phase"][sl].copy()
    flight = phase == FLIGHT
    # force-free samples: the row of eq. (14) says 0; the positions meet it to rounding
    acc[zdd + g <= force_eps * g, :2] = 0.0
    zmp = np.zeros((m, 3))
    zmp[:, :2] = buf["zmp"][sl]
    zmp[flight] = np.nan
    with np.errstate(invalid="ignore", divide="ignore"):
        stiff = np.sqrt(z / (zdd + g))
    stiff[flight] = np.nan
    idx = np.arange(i, i + m)
    t: FloatArray = np.asarray(idx * dt, dtype=np.float64)
    foot_pos = np.empty((m, 2, 3))
    foot_pos[:, LEFT] = feet.positions(LEFT, idx)
    foot_pos[:, RIGHT] = feet.positions(RIGHT, idx)
    cols = {
        "com_pos": pos,
        "com_vel": vel,
        "com_acc": acc,
        "zmp": zmp,
        "phase": phase,
        "contact": buf["contact"][sl].copy(),
        "foot_pos": foot_pos,
        "stiffness": stiff,
    }
    return Samples(t, cols, np.broadcast_to(command, (m, 2)).copy())
