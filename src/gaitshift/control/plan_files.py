"""A plan handed from the planner's process to the controller's through a file, its arrays mapped, not copied.

Unpickled in the tick that adopts it, a plan's arrays are read and copied whole, and the tick pays for the
plan's whole length (measured when a live plan still held every sample from the start of the run: 1.8 ms
p50 against 0.8 ms for a tick without a plan, 12 s into the G1 tour; a live plan is now a window of at
most ~1 400 samples, :mod:`gaitshift.trajectory.window`, and a TV-LIPM or VHIP plan is the whole run).
Here the worker writes the plan with pickle protocol 5, its arrays' bytes out of band after the pickle
(each on a 64-byte boundary); the tick maps the file copy-on-write and hands pickle the mapped buffers,
so that the arrays are views of the mapping: the pages a tick reads are loaded as it reads them (the
plan's current stretch), whatever the plan's length. The mapping lives
as long as an array of the plan does. The reader leaves the file: unmapping a file that is still there
only drops the pages the tick touched, while the last unmapping of a removed file frees all its pages
(5 ms for a 43 MB plan, 21 ms for 180 MB, in the tick that let the old plan go); the writer's side
removes it once the reader says it no longer maps it. Layout::

    b"GSPF" | uint64 pickle length | uint64 buffer count | uint64 offset, length per buffer
    | pickle | buffers
"""

import mmap
import pickle
import struct
from pathlib import Path
from typing import Any

__all__ = ["PlanFolder", "read_plan", "write_plan"]

_MAGIC = b"GSPF"
_ALIGN = 64


def write_plan(path: Path, obj: Any) -> None:
    """Write ``obj`` to ``path`` (module docstring)."""
    buffers: list[pickle.PickleBuffer] = []
    head = pickle.dumps(obj, protocol=5, buffer_callback=buffers.append)
    raws = [b.raw() for b in buffers]
    table_end = len(_MAGIC) + 16 + 16 * len(raws)
    offset = table_end + len(head)
    spans = []
    for raw in raws:
        offset += -offset % _ALIGN
        spans.append((offset, raw.nbytes))
        offset += raw.nbytes
    with open(path, "wb") as f:
        f.write(_MAGIC + struct.pack("<2Q", len(head), len(raws)))
        f.write(b"".join(struct.pack("<2Q", *span) for span in spans))
        f.write(head)
        for (start, _), raw in zip(spans, raws, strict=True):
            f.seek(start)
            f.write(raw)


def read_plan(path: Path) -> Any:
    """The object written by :func:`write_plan` at ``path``, mapped (the file stays: module docstring)."""
    with open(path, "rb") as f:
        view = memoryview(mmap.mmap(f.fileno(), 0, access=mmap.ACCESS_COPY))
    if bytes(view[: len(_MAGIC)]) != _MAGIC:
        raise ValueError(f"{path}: not a plan file")
    n_head, n_buf = struct.unpack_from("<2Q", view, len(_MAGIC))
    table = len(_MAGIC) + 16
    spans = [struct.unpack_from("<2Q", view, table + 16 * k) for k in range(n_buf)]
    head = view[table + 16 * n_buf : table + 16 * n_buf + n_head]
    return pickle.loads(head, buffers=[view[start : start + size] for start, size in spans])


class PlanFolder:
    """A worker's numbered plan files in ``folder``: ``<n>.plan``, written whole under another name first
    (a reader told of plan ``n`` never finds it half written), read mapped, removed by the writer's side once
    the reader no longer maps them.

    Attributes:
        folder: where the files are. freed: the files numbered up to this one are removed.
    """

    def __init__(self, folder: Path) -> None:
        self.folder, self.freed = Path(folder), 0

    def write(self, n: int, obj: Any) -> None:
        """Write plan ``n`` (:func:`write_plan`), then name it."""
        tmp = self.folder / f"{n}.tmp"
        write_plan(tmp, obj)
        tmp.rename(self.folder / f"{n}.plan")

    def read(self, n: int) -> Any:
        """Plan ``n``, mapped (:func:`read_plan`)."""
        return read_plan(self.folder / f"{n}.plan")

    def free_before(self, n: int) -> None:
        """Remove the files of the plans before ``n`` (the reader maps none of them any more)."""
        for k in range(self.freed + 1, n):
            (self.folder / f"{k}.plan").unlink(missing_ok=True)
        self.freed = max(self.freed, n - 1)
