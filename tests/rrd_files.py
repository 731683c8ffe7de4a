"""Reading a Rerun recording (``.rrd``) back in the tests, with the Rerun SDK's ``rerun.chunk.RrdReader``."""

from __future__ import annotations

import numpy as np


def read(path):
    """{entity: {column: [(time s, value), ...]}} of a .rrd file (static rows get time None)."""
    import rerun.chunk as rr_chunk

    out: dict[str, dict[str, list]] = {}
    for chunk in rr_chunk.RrdReader(path).stream():
        batch = chunk.to_record_batch()
        cols = batch.schema.names
        times = [None] * batch.num_rows
        if "time" in cols:  # durations, ns
            times = [None if t is None else t / 1e9 for t in batch.column("time").cast("int64").to_pylist()]
        for name in cols:
            if ":" in name and not name.startswith("rerun."):
                values = batch.column(name).to_pylist()
                out.setdefault(chunk.entity_path.lstrip("/"), {}).setdefault(name, []).extend(
                    zip(times, values, strict=True)
                )
    return out


def series(rec, entity, column="Scalars:scalars"):
    """(times s, values) of a scalar timeline of ``read``'s output, sorted by time (static rows left out)."""
    rows = sorted((t, v[0] if isinstance(v, list) else v) for t, v in rec[entity][column] if t is not None)
    return np.array([r[0] for r in rows]), np.array([r[1] for r in rows], dtype=float)
