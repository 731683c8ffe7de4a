"""Convex hulls in the horizontal plane (support polygons of soles).

Andrew's monotone chain: the points sorted by (x, y), the lower and the upper chain each keep a point
only while the turn it makes is counter-clockwise (cross product > 0), so the hull comes out
counter-clockwise without collinear or repeated points.
"""

from __future__ import annotations

import numpy as np

__all__ = ["convex_hull_xy", "hull_margin", "hull_margins"]


def convex_hull_xy(points: np.ndarray) -> np.ndarray:
    """Vertices (k, 3) of the convex hull of ``points`` (n, 3) in their x-y plane, counter-clockwise
    (Andrew's monotone chain); collinear and repeated points are dropped."""
    pts = np.asarray(points, float).reshape(-1, 3)
    order = sorted(range(len(pts)), key=lambda i: (pts[i, 0], pts[i, 1]))

    def half(idx: list[int]) -> list[int]:
        out: list[int] = []
        for i in idx:
            while len(out) >= 2:
                a, b = pts[out[-2], :2], pts[out[-1], :2]
                if (b[0] - a[0]) * (pts[i, 1] - a[1]) - (b[1] - a[1]) * (pts[i, 0] - a[0]) > 1e-12:
                    break
                out.pop()
            out.append(i)
        return out

    if len(pts) <= 2:
        return pts
    lower, upper = half(order), half(order[::-1])
    return pts[lower[:-1] + upper[:-1]]


def hull_margin(points: np.ndarray, p: np.ndarray) -> float:
    """min over the edges of the convex hull of ``points`` (M, 2) of the inward distance of ``p`` (2,)
    from the edge's line, m: >= 0 inside (the distance to the nearest edge), < 0 outside."""
    return float(hull_margins(points, np.reshape(np.asarray(p, float), (1, 2)))[0])


def hull_margins(points: np.ndarray, ps: np.ndarray) -> np.ndarray:
    """:func:`hull_margin` of every row of ``ps`` (n, 2) against the one hull of ``points`` (M, 2), m, shape (n,)."""
    pts = np.asarray(points, float).reshape(-1, 2)
    hull = convex_hull_xy(np.column_stack([pts, np.zeros(len(pts))]))[:, :2]
    a, b = hull, np.roll(hull, -1, axis=0)
    edge = b - a
    normal = np.stack([-edge[:, 1], edge[:, 0]], axis=1) / np.linalg.norm(edge, axis=1, keepdims=True)  # inward
    rel = np.asarray(ps, float).reshape(-1, 1, 2) - a  # (n, k, 2): each point from each edge's start
    return np.asarray(np.min(np.sum(normal * rel, axis=2), axis=1))
