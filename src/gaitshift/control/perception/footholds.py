"""Footholds on believed ground: the place nearest the planned one where a sole may stand.

A foothold (sole centre ``x`` m along the path, sole ``length`` x ``width`` m at yaw ``psi``, so half
its extent along x is :math:`l = \\tfrac12 (\\text{length} |\\cos\\psi| + \\text{width} |\\sin\\psi|)`)
is *safe* on the believed terrain when

.. math::

    b_i + l + m_i \\le x \\le b_{i+1} - l - m_{i+1}, \\qquad
    |x - x_p| \\le s_{max}, \\qquad |z(x) - z_p| \\le h_{max}, \\qquad
    x + l \\le x_{seen}                                                             (1)

for two neighbour breaks :math:`b_i < b_{i+1}` of the belief (a sole on one piece), the margins
:math:`m_i` = ``edge_margin`` at a step edge and 0 at a ramp's kink (both scaled down alike where the
piece leaves less room, as :meth:`Terrain.clamp_sole` does), the previous foothold
:math:`(x_p, z_p)` (the stride and the rise within the scenario's limits), and the far end of the seen
ground :math:`x_{seen}` (no sole on ground nobody saw). The belief's *gaps* (a riser's cells, the
shadow of a step down: an edge lies somewhere in them) are pieces no sole overlaps, their ends step
edges. :func:`place` returns the safe x nearest the
planned one, or None when the path is blocked: the piece under the planned x is too high or too low
to step on, or lies beyond the seen ground, or no reachable place is safe. The walk must then stop
before it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from gaitshift.models.terrain import Terrain

__all__ = ["FootholdRules", "place"]


@dataclass(frozen=True)
class FootholdRules:
    """Eq. (1)'s constants: the sole ``length`` and ``width`` (m), ``edge_margin`` (m from a step edge),
    ``max_stride`` (m along x from the previous foothold) and ``max_rise`` (m of height from it)."""

    length: float
    width: float
    edge_margin: float
    max_stride: float
    max_rise: float


def place(
    belief: Terrain,
    seen_to: float | None,
    x: float,
    yaw: float,
    prev: tuple[float, float],
    rules: FootholdRules,
    gaps: Sequence[tuple[float, float]] = (),
) -> float | None:
    """The safe x (eq. (1)) nearest the planned ``x`` (m) for a sole at ``yaw`` (rad) after the foothold
    ``prev`` (x m, z m), on ``belief`` seen up to ``seen_to`` m (None: no sight condition, for a foothold
    that will be placed again before it is committed); None when the path is blocked (module docstring).
    ``gaps`` (m, from, to) hold an edge somewhere: their ends count as step edges and no sole overlaps
    them."""
    seen_to = math.inf if seen_to is None else seen_to
    half = 0.5 * (rules.length * abs(math.cos(yaw)) + rules.width * abs(math.sin(yaw)))
    ends = np.array(gaps, float).reshape(-1)
    inner = np.unique(np.r_[belief.breaks(), ends])
    b = np.r_[-np.inf, inner, np.inf]
    step = np.r_[False, np.isin(inner, belief.steps()) | np.isin(inner, ends), False]
    margin = np.where(step, rules.edge_margin, 0.0)
    room = np.diff(b) - 2 * half  # beyond the sole, on each piece
    both = margin[:-1] + margin[1:]
    scale = np.clip(np.divide(room, both, out=np.ones_like(room), where=both > 0), 0.0, 1.0)
    m0, m1 = margin[:-1] * scale, margin[1:] * scale
    lo = np.maximum(b[:-1] + half + m0, prev[0] - rules.max_stride)
    hi = np.minimum(b[1:] - half - m1, min(prev[0] + rules.max_stride, seen_to - half))
    if x - half > seen_to or abs(float(belief.height(x)) - prev[1]) > rules.max_rise:
        return None  # the planned place itself is unseen, or too high or too low
    fin = np.clip(b, -1e9, 1e9)
    mid = 0.5 * (fin[:-1] + fin[1:])
    in_gap = np.zeros(len(mid), bool)
    for g0, g1 in gaps:
        in_gap |= (mid > g0) & (mid < g1)
    cand = np.clip(x, lo, hi)
    ok = (lo <= hi) & ~in_gap & (np.abs(belief.height(cand) - prev[1]) <= rules.max_rise)
    if not ok.any():
        return None
    cand = cand[ok]
    return float(cand[np.argmin(np.abs(cand - x))])
