"""The cases of a sample spec (``sample: {cases, seed}``): random draws instead of the product.

Case ``i`` takes, per axis ``a`` of :data:`gaitshift.campaign.axes.AXES`:

* an interval ``{low, high}``: ``U(low, high)`` (a float axis, rounded to 9 significant digits so that
  the value reads back the same from the store), or a uniform integer in ``[low, high]`` (an int axis);
* a list or a range: one of its values, each with probability ``1 / len``;
* an axis the spec leaves out: its default.

Each axis draws from its own generator, seeded by ``(seed, crc32(a))``: adding an axis to a spec does
not change the draws of the others, and the same spec always gives the same cases (and hashes).
"""

from __future__ import annotations

import zlib
from typing import Any

import numpy as np

from gaitshift.campaign.axes import AXES
from gaitshift.campaign.spec import CampaignSpec, is_interval

__all__ = ["draw_columns"]


def _column(spec: CampaignSpec, name: str, values: list[Any], n: int, seed: int) -> list[Any]:
    """The ``n`` values of axis ``name`` (module docstring); ``values``: its checked values or ends."""
    rng = np.random.default_rng([seed, zlib.crc32(name.encode())])
    if is_interval(spec.axes.get(name)):
        low, high = values[0], values[-1]
        if AXES[name].kind == "int":
            return [int(v) for v in rng.integers(low, high + 1, n)]
        return [float(f"{v:.9g}") for v in rng.uniform(low, high, n)]
    if len(values) == 1:
        return values * n
    return [values[i] for i in rng.integers(0, len(values), n)]


def draw_columns(spec: CampaignSpec, values: dict[str, list[Any]]) -> dict[str, list[Any]]:
    """Axis -> its ``spec.sample.cases`` values (module docstring), from the checked ``values`` of
    :meth:`CampaignSpec.axis_values`."""
    assert spec.sample is not None
    n, seed = spec.sample.cases, spec.sample.seed
    return {name: _column(spec, name, vals, n, seed) for name, vals in values.items()}
