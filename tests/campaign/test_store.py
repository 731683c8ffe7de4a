"""The store keeps one row per case hash (writing a case again replaces its row), leaves no temporary
file, reads part files of an older schema with the missing columns null, and marks the dataset
complete only when every expected hash has its row."""

from __future__ import annotations

import pyarrow as pa
import pyarrow.parquet as pq

from gaitshift.campaign.store import SCHEMA, Store


def _row(h: str, fell: bool) -> dict:
    return dict.fromkeys(SCHEMA.names) | {"case_hash": h, "fell": fell, "task": "simulate", "speed": 0.5}


def test_one_row_per_hash_and_complete_only_when_all_done(tmp_path):
    """Two writes of case a, one of b: two rows, a's the latest; complete needs a, b (not a, b, c)."""
    store = Store(tmp_path)
    store.start("task: simulate\n")
    store.write({"row": _row("a", True), "motion": None})
    store.write({"row": _row("a", False), "motion": None})
    store.write({"row": _row("b", True), "motion": None})
    rows = {r["case_hash"]: r for r in store.table().to_pylist()}
    assert set(rows) == {"a", "b"} and rows["a"]["fell"] is False
    assert sorted(p.name for p in (tmp_path / "parts").iterdir()) == ["a.parquet", "b.parquet"]
    assert not store.finish({"a", "b", "c"}) and not store.complete_marker.exists()
    assert store.finish({"a", "b"}) and store.complete_marker.exists()
    store.start("task: simulate\n")  # a new run drops the marker until it ends
    assert not store.complete_marker.exists()


def test_old_part_files_read_with_missing_columns_null(tmp_path):
    """A part file without ``plan_gaits`` (an older version) reads with that column null."""
    store = Store(tmp_path)
    store.start("x")
    store.write({"row": _row("new", False) | {"plan_gaits": "walk"}, "motion": None})
    old = pa.table({"case_hash": ["old"], "fell": [True], "speed": [0.3]})
    pq.write_table(old, tmp_path / "parts" / "old.parquet")
    rows = {r["case_hash"]: r for r in store.table().to_pylist()}
    assert rows["old"]["plan_gaits"] is None and rows["old"]["speed"] == 0.3 and rows["new"]["plan_gaits"] == "walk"
    assert store.table().schema.equals(SCHEMA)
