"""Strict JSON from numpy-laden Python objects: no NaN or infinity in any output file."""

from __future__ import annotations

import math
from typing import Any

import numpy as np


def finite_json(obj: Any) -> Any:
    """``obj`` as plain JSON values, with every non-finite float replaced by None.

    Dicts (keys become ``str``), lists, tuples and arrays are converted recursively; numpy scalars
    become Python ``float``/``int``/``bool``. The result passes ``json.dumps(..., allow_nan=False)``.
    """
    if isinstance(obj, dict):
        return {str(k): finite_json(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [finite_json(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return finite_json(obj.tolist())
    if isinstance(obj, (float, np.floating)):
        return float(obj) if math.isfinite(obj) else None
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    return obj
