"""Array type aliases shared by the typed layers (models, gait, planners).

``FloatArray`` is a float64 array of any shape (the shape is given in each docstring), ``IntArray``
an integer index array, ``BoolArray`` a mask. ``FloatLike`` is what a function that broadcasts accepts:
a Python float or a float64 array.
"""

from __future__ import annotations

from typing import TypeAlias

import numpy as np
import numpy.typing as npt

__all__ = ["BoolArray", "FloatArray", "FloatLike", "Int8Array", "IntArray"]

FloatArray: TypeAlias = npt.NDArray[np.float64]
IntArray: TypeAlias = npt.NDArray[np.intp]
Int8Array: TypeAlias = npt.NDArray[np.int8]
BoolArray: TypeAlias = npt.NDArray[np.bool_]
FloatLike: TypeAlias = float | FloatArray
