"""The campaign dataset on disk: one small Parquet part file per case, written atomically.

Layout of ``DIR``::

    spec.yaml            the spec as run (its axes and settings), written at the start
    parts/<hash>.parquet one row: the case's parameters and its results (written as the case ends)
    motions/<hash>.npz   task ``reference``: the whole-body motion of the case
    index.csv            task ``reference``: robot, gait, speed, yaw_rate, duration, file (at the end)
    complete             written last, only when every case of the spec has its row

A part file is written to a temporary name and renamed (:mod:`gaitshift.common.atomic`), so a part
file is whole or absent; its name is the case hash, so a case has at most one row however often it
runs (a re-run after a lost worker replaces the file with an identical-key row). Resume = skip the
hashes that have a part file. A crash or Ctrl-C loses only the cases in flight.
"""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.dataset as ds
import pyarrow.parquet as pq

from gaitshift.campaign.axes import AXES
from gaitshift.campaign.execute import METRICS
from gaitshift.common.atomic import atomic_path
from gaitshift.errors import InputError

__all__ = ["SCHEMA", "Store"]

_SETTINGS = {
    "task": pa.string(),
    "duration": pa.float64(),
    "control_period": pa.float64(),
    "reference_mode": pa.string(),
    "reference_rate": pa.float64(),
}
_KINDS = {"float": pa.float64(), "int": pa.int64(), "str": pa.string()}
_METRIC_TYPES = {"bool": pa.bool_(), "float64": pa.float64(), "int64": pa.int64(), "string": pa.string()}

#: the Arrow schema of a row: run settings, every axis, the metrics, the case hash
SCHEMA = pa.schema(
    [pa.field(k, t) for k, t in _SETTINGS.items()]
    + [pa.field(k, _KINDS[a.kind]) for k, a in AXES.items()]
    + [pa.field(k, _METRIC_TYPES[t]) for k, t in METRICS.items()]
    + [pa.field("case_hash", pa.string())]
)

#: columns of the reference index file
INDEX_COLUMNS = ("robot", "gait", "speed", "yaw_rate", "duration", "file")


class Store:
    """The dataset folder of one campaign (module docstring)."""

    def __init__(self, root: str | Path) -> None:
        self.root = Path(root)
        self.parts = self.root / "parts"

    @property
    def complete_marker(self) -> Path:
        return self.root / "complete"

    def check(self, spec_text: str) -> None:
        """Nothing is written here.

        Raises:
            InputError: the folder holds another campaign's spec (a different spec text).
        """
        spec_file = self.root / "spec.yaml"
        if spec_file.exists() and spec_file.read_text() != spec_text:
            raise InputError("--out", str(self.root), "an empty folder or one holding this same spec's campaign")

    def start(self, spec_text: str) -> None:
        """Create the folders, record the spec, and drop a stale ``complete`` marker (the dataset is
        complete again only when this run ends with every case done).

        Raises:
            InputError: the folder holds another campaign's spec (a different spec text).
        """
        self.check(spec_text)
        self.parts.mkdir(parents=True, exist_ok=True)
        spec_file = self.root / "spec.yaml"
        if not spec_file.exists():
            with atomic_path(spec_file, "--out") as tmp:
                tmp.write_text(spec_text)
        self.complete_marker.unlink(missing_ok=True)

    def done(self) -> set[str]:
        """The hashes of the cases with a row."""
        return {p.stem for p in self.parts.glob("*.parquet")} if self.parts.is_dir() else set()

    def write(self, result: dict[str, Any]) -> None:
        """Write one case's result (``{"row", "motion"}`` of :func:`~gaitshift.campaign.execute.run_case`):
        the motion first, then the row, each atomically (the row marks the case done)."""
        row = dict(result["row"])
        h = row["case_hash"]
        if result.get("motion") is not None:
            rel = f"motions/{h}.npz"
            m = result["motion"]
            with atomic_path(self.root / rel) as tmp, open(tmp, "wb") as fh:
                np.savez_compressed(fh, t=m["t"], qpos=m["qpos"], qvel=m["qvel"], meta=np.array(m["meta"]))
            row["motion_file"] = rel
        table = pa.Table.from_pylist([{k: row.get(k) for k in SCHEMA.names}], schema=SCHEMA)
        with atomic_path(self.parts / f"{h}.parquet") as tmp:
            pq.write_table(table, tmp)

    def table(self) -> pa.Table:
        """Every row written so far, sorted by case hash, in :data:`SCHEMA` (columns a part file of an
        older version lacks are null; an empty table when there is no row). Only the ``*.parquet``
        files of ``parts/`` are read (a stray note or a hidden temporary file there is not a row).

        Raises:
            InputError: naming the first part file that is not a readable row of this schema.
        """
        files = sorted(p for p in self.parts.glob("*.parquet") if p.is_file()) if self.parts.is_dir() else []
        if not files:
            return SCHEMA.empty_table()
        try:
            dataset = ds.dataset([str(p) for p in files], format="parquet", schema=SCHEMA)
            return dataset.to_table().sort_by("case_hash")
        except (pa.ArrowInvalid, pa.ArrowTypeError, pa.ArrowNotImplementedError, OSError) as exc:
            bad, why = next(((p, e) for p in files if (e := _unreadable(p)) is not None), (self.parts, exc))
            raise InputError(
                f"parts/{bad.name}", str(bad), f"part files written by a campaign ({_first_line(why)})"
            ) from None

    def finish(self, expected: set[str]) -> bool:
        """Write the reference index and the ``complete`` marker when every ``expected`` hash has its
        row; return whether the dataset is complete."""
        if not expected <= self.done():
            return False
        rows = [r for r in self.table().to_pylist() if r["case_hash"] in expected]
        if any(r["task"] == "reference" for r in rows):
            self._write_index(rows)
        with atomic_path(self.complete_marker) as tmp:
            tmp.write_text(json.dumps({"cases": len(expected)}) + "\n")
        return True

    def _write_index(self, rows: list[dict[str, Any]]) -> None:
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow(INDEX_COLUMNS)
        for r in sorted(rows, key=lambda r: r["case_hash"]):
            if r["motion_file"] is None:
                continue
            meta = json.loads(str(np.load(self.root / r["motion_file"])["meta"]))
            robot = r["robot"] or meta.get("robot_name")
            w.writerow([robot, r["plan_gaits"], r["speed"], r["yaw_rate"], r["plan_duration"], r["motion_file"]])
        with atomic_path(self.root / "index.csv") as tmp:
            tmp.write_text(buf.getvalue())


def _unreadable(path: Path) -> BaseException | None:
    """Why the part file ``path`` is not one row of :data:`SCHEMA` (None: it is)."""
    try:
        ds.dataset(str(path), format="parquet", schema=SCHEMA).to_table()
    except (pa.ArrowInvalid, pa.ArrowTypeError, pa.ArrowNotImplementedError, OSError) as exc:
        return exc
    return None


def _first_line(exc: BaseException) -> str:
    """The first line of an exception's message, at most 100 characters."""
    lines = str(exc).strip().splitlines()
    return (lines[0] if lines else type(exc).__name__)[:100]
