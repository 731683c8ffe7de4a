"""The ZMP boxes of eq. (7) of paper 001 at every phase boundary.

At each boundary k the ZMP c_k must lie in a box ``lo <= R_k^T (c_k - origin_k) <= hi`` in the frame
of the supporting sole: the sole of the single-support phase next to the boundary, or, when both
neighbouring phases are double support, the rectangle spanning both soles (mid-point origin,
mid-yaw axes). The half sizes are the sole's minus ``foot.zmp_margin``. The vertical ZMP has its own
1-D box ``zmp_z`` around the sole height. The box origin is also the regularisation target of the ZMP
in the boundary solve (:mod:`gaitshift.planners.tvlip.kkt`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from gaitshift.gait.sequence import GaitSequence
from gaitshift.models.arrays import FloatArray
from gaitshift.trajectory.contract import DS, LEFT, RIGHT, SS

__all__ = ["Boxes", "boxes_from_flight", "build_boxes"]


@dataclass(frozen=True)
class Boxes:
    """Eq. (7) for every boundary: ZMP box in a local frame.

    Attributes (K+1 boundaries, d = 2 for xy or 1 for z):
        origin: (K+1, d) box frame origin (sole centre or mid-point of both soles), m.
        rot: (K+1, d, d) columns are the local axes in world coordinates (R_foot).
        lo, hi: (K+1, d) bounds of R^T (c - origin), m.

    The origin is also the regularisation target of the ZMP.
    """

    origin: FloatArray
    rot: FloatArray
    lo: FloatArray
    hi: FloatArray


def build_boxes(
    seq: GaitSequence, foot_size: Sequence[float], margin: float, zmp_z: Sequence[float]
) -> tuple[Boxes, Boxes]:
    """ZMP boxes (xy and z) at every boundary: the sole of the single-support phase next to the
    boundary, or the rectangle spanning both soles when both neighbouring phases are double support.

    ``foot_size`` (length, width) and ``margin`` in m; ``zmp_z`` (lo, hi) the vertical ZMP range
    around the sole height, m. Returns (xy boxes with d = 2, z boxes with d = 1)."""
    kinds = seq.kind
    on = seq.on
    fs = seq.footstep_array
    K = len(kinds)
    half = np.array([foot_size[0] / 2 - margin, foot_size[1] / 2 - margin])
    prev = np.r_[-1, kinds]  # kind of the phase before / after each boundary (-1: none)
    nxt = np.r_[kinds, -1]
    b = np.arange(K + 1)
    ss = np.where(prev == SS, b - 1, np.where(nxt == SS, b, -1))  # neighbouring single support
    ds = np.where(prev == DS, b - 1, b)  # otherwise a neighbouring double support
    on_ss = on[np.maximum(ss, 0)].max(axis=1)
    on_ds = on[np.minimum(ds, K - 1)]
    a, bb = fs[on_ds[:, LEFT]], fs[on_ds[:, RIGHT]]
    mid_yaw = np.arctan2(np.sin(a[:, 3]) + np.sin(bb[:, 3]), np.cos(a[:, 3]) + np.cos(bb[:, 3]))
    d = a[:, :2] - bb[:, :2]
    sep = np.abs(
        np.stack(
            [
                np.cos(mid_yaw) * d[:, 0] + np.sin(mid_yaw) * d[:, 1],
                -np.sin(mid_yaw) * d[:, 0] + np.cos(mid_yaw) * d[:, 1],
            ],
            -1,
        )
    )
    is_ss = (ss >= 0)[:, None]
    foot = fs[on_ss]
    origin = np.where(is_ss, foot[:, :2], (a[:, :2] + bb[:, :2]) / 2)
    yaw = np.where(is_ss[:, 0], foot[:, 3], mid_yaw)
    hi = np.where(is_ss, half, half + sep / 2)
    zo = np.where(is_ss[:, 0], foot[:, 2], (a[:, 2] + bb[:, 2]) / 2)
    cy, sy = np.cos(yaw), np.sin(yaw)
    rot = np.stack([np.stack([cy, -sy], -1), np.stack([sy, cy], -1)], -2)  # columns: local x, y
    xy = Boxes(origin, rot, -hi, hi)
    z = Boxes(zo[:, None], np.ones((K + 1, 1, 1)), np.full((K + 1, 1), zmp_z[0]), np.full((K + 1, 1), zmp_z[1]))
    return xy, z


def boxes_from_flight(
    sub: GaitSequence, foot_size: Sequence[float], margin: float, zmp_z: Sequence[float]
) -> tuple[Boxes, Boxes]:
    """Boxes when the first (truncated) phase of ``sub`` is a flight: boundary 0's ZMP does not act;
    give it the box of the landing boundary so that the regularisation has a target."""
    xy, z = build_boxes(GaitSequence(sub.phases[1:], sub.footsteps, sub.step_gait), foot_size, margin, zmp_z)
    return _repeat_first(xy), _repeat_first(z)


def _repeat_first(b: Boxes) -> Boxes:
    """The same boxes with boundary 0's box repeated in front."""
    origin, rot, lo, hi = (np.concatenate([arr[:1], arr]) for arr in (b.origin, b.rot, b.lo, b.hi))
    return Boxes(origin, rot, lo, hi)
