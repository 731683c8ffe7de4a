"""A ring buffer of planned samples addressed by global sample index (streaming generators).

A streaming generator plans ahead of what it emits: each planning instant appends a block of samples,
each control tick reads (and then releases) the oldest ones. :class:`SampleBuffer` stores named
columns (any per-sample shape and dtype, fixed at construction) and keeps the addressing global: the
sample ``i`` of the run is ``buf["c"][i]`` whatever has been dropped before it. Samples before
:meth:`SampleBuffer.release` are dropped when space runs out, so memory and copy cost stay bounded
by the look-ahead, however long the run.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, overload

import numpy as np
import numpy.typing as npt

__all__ = ["Column", "SampleBuffer"]


class Column:
    """One column of a :class:`SampleBuffer`, indexed by global sample index (ints and slices)."""

    __slots__ = ("buf", "name")

    def __init__(self, buf: SampleBuffer, name: str):
        self.buf, self.name = buf, name

    def _key(self, key: int | slice) -> int | slice:
        base = self.buf.base
        if isinstance(key, slice):
            return slice(
                None if key.start is None else key.start - base, None if key.stop is None else key.stop - base, key.step
            )
        return key - base

    @overload
    def __getitem__(self, key: slice) -> np.ndarray: ...
    @overload
    def __getitem__(self, key: int) -> Any: ...
    def __getitem__(self, key: int | slice) -> Any:
        """A view of the rows for a slice; for an int the row (an array for a column with a
        per-sample shape, a numpy scalar otherwise, hence ``Any``)."""
        return self.buf.arrays[self.name][self._key(key)]

    def __setitem__(self, key: int | slice, value: npt.ArrayLike) -> None:
        self.buf.arrays[self.name][self._key(key)] = value


class SampleBuffer:
    """Planned samples in named columns, addressed by global sample index.

    Args:
        fields: column name -> (per-sample shape, dtype), e.g. ``{"c": ((2,), np.float64)}``.
        capacity: initial number of rows (grows when the look-ahead needs more).

    Attributes:
        n: global index one past the last planned sample.
        base: global index of row 0 of the storage.
        arrays: the storage, one array per column, shape (capacity, *shape).
    """

    def __init__(self, fields: Mapping[str, tuple[tuple[int, ...], npt.DTypeLike]], capacity: int = 4096):
        self.n = 0
        self.base = 0
        self._keep = 0  # rows before this global index may be dropped
        self.arrays: dict[str, np.ndarray] = {
            k: np.zeros((capacity, *shape), dtype=dtype) for k, (shape, dtype) in fields.items()
        }
        self._columns = {k: Column(self, k) for k in fields}

    def __getitem__(self, name: str) -> Column:
        """The column ``name`` (index it with global sample indices)."""
        return self._columns[name]

    def rows(self, start: int, stop: int) -> dict[str, np.ndarray]:
        """Copies of every column's rows ``start .. stop-1`` (global indices)."""
        a, b = start - self.base, stop - self.base
        return {k: arr[a:b].copy() for k, arr in self.arrays.items()}

    def release(self, upto: int) -> None:
        """Samples before global index ``upto`` are no longer needed."""
        self._keep = max(self._keep, upto)

    def write(self, start: int, **arrays: np.ndarray) -> None:
        """Write equally long blocks of some columns from global index ``start`` on (overwriting
        planned samples from there, appending beyond ``n``)."""
        m = len(next(iter(arrays.values())))
        cap = len(next(iter(self.arrays.values())))
        if start + m - self.base > cap:
            drop = min(self._keep, start) - self.base
            if drop > 0:  # slide the live rows to the front
                live = self.n - self.base
                for arr in self.arrays.values():
                    arr[: live - drop] = arr[drop:live]
                self.base += drop
            if start + m - self.base > cap:  # still too small: grow
                new = max(2 * cap, start + m - self.base + 1024)
                for k, arr in self.arrays.items():
                    grown = np.zeros((new, *arr.shape[1:]), dtype=arr.dtype)
                    grown[: self.n - self.base] = arr[: self.n - self.base]
                    self.arrays[k] = grown
        for k, v in arrays.items():
            self.arrays[k][start - self.base : start - self.base + m] = v
        self.n = max(self.n, start + m)
