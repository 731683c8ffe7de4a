"""An 8-case campaign on a LocalCluster of 2 worker processes: a worker is killed (SIGKILL) on its
first case, the scheduler re-runs that case elsewhere, and the dataset holds each case hash exactly
once; a second run skips everything; after deleting two rows a third run re-runs exactly those two.
The rows are the physics of the plan, not copies: faster commands give longer strides, so the whole-
body joint speeds grow with the speed."""

from __future__ import annotations

from pathlib import Path

import dask
import distributed  # noqa: F401  (loads its config defaults: the config.set below then restores only the preload)
import pyarrow.parquet as pq
import pytest

from gaitshift.campaign.cases import expand
from gaitshift.campaign.run import run_campaign
from gaitshift.campaign.spec import load_spec
from gaitshift.campaign.store import SCHEMA, Store

WALK = Path(__file__).resolve().parents[2] / "docs" / "campaigns" / "g1-walk.yaml"
PRELOAD = Path(__file__).with_name("fault_preload.py")
MARKER_ENV = "GAITSHIFT_TEST_CAMPAIGN_FAULT"  # fault_preload.MARKER_ENV
SPEC = f"""
name: tiny
task: plan
duration: 1.0
axes:
  scenario: [{WALK}]
  speed: [0.25, 0.55]
  mass_scale: [1.0, 1.1]
  friction: {{start: 0.5, stop: 1.0, step: 0.5}}
"""


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    """The tiny campaign run once with a worker killed mid-run: (spec, folder, summary, fault marker)."""
    root = tmp_path_factory.mktemp("campaign")
    (root / "spec.yaml").write_text(SPEC)
    spec = load_spec(root / "spec.yaml")
    marker = root / "killed"
    mp = pytest.MonkeyPatch()
    mp.setenv(MARKER_ENV, str(marker))  # the worker processes inherit it
    try:  # the fault lives in the test: a worker preload that kills the first case's process
        with dask.config.set({"distributed.worker.preload": [str(PRELOAD)]}):
            summary = run_campaign(spec, SPEC, root / "out", workers=2, echo=lambda line: None)
    finally:
        mp.undo()
    return spec, root / "out", summary, marker


def test_worker_killed_mid_run_and_every_case_exactly_once(campaign):
    """A worker process died (the marker holds its pid), yet all 8 cases ran and each hash has one row."""
    spec, out, summary, marker = campaign
    assert marker.exists() and int(marker.read_text()) > 0
    assert summary.cases == 8 and summary.ran == 8 and summary.lost == 0 and summary.complete
    table = Store(out).table()
    hashes = table.column("case_hash").to_pylist()
    assert sorted(hashes) == sorted(c["case_hash"] for c in expand(spec)) and len(set(hashes)) == 8
    assert (out / "complete").exists()
    assert table.schema.equals(SCHEMA)
    part = next((out / "parts").glob("*.parquet"))
    assert pq.read_table(part).num_rows == 1


def test_rows_follow_the_commanded_speed(campaign):
    """Each row carries its parameters; the faster command moves the joints faster (same other axes),
    and the model-error axes (mass, friction) do not change a kinematic plan."""
    _, out, _, _ = campaign
    rows = Store(out).table().to_pylist()
    assert all(r["error"] is None and r["gaitshift_version"] for r in rows)
    by = {(r["speed"], r["mass_scale"], r["friction"]): r["joint_speed_fraction"] for r in rows}
    for m in (1.0, 1.1):
        for mu in (0.5, 1.0):
            assert by[(0.55, m, mu)] > by[(0.25, m, mu)] > 0
            assert by[(0.55, m, mu)] == by[(0.55, 1.0, 0.5)]


def test_resume_skips_done_and_reruns_only_missing(campaign):
    """Run again: 0 run, 8 skipped. Delete two rows and the marker: the next run runs exactly those two,
    and the dataset again holds each hash once and is complete."""
    spec, out, _, _ = campaign
    again = run_campaign(spec, SPEC, out, workers=2, echo=lambda line: None)
    assert (again.skipped, again.ran, again.complete) == (8, 0, True)
    gone = sorted((out / "parts").glob("*.parquet"))[:2]
    for p in gone:
        p.unlink()
    (out / "complete").unlink()
    third = run_campaign(spec, SPEC, out, workers=1, echo=lambda line: None)
    assert (third.skipped, third.ran, third.complete) == (6, 2, True)
    hashes = Store(out).table().column("case_hash").to_pylist()
    assert len(hashes) == len(set(hashes)) == 8 and {p.stem for p in gone} <= set(hashes)


def test_a_folder_of_another_spec_is_refused(campaign, tmp_path):
    """Resuming into a folder that holds a different spec is an error (no mixed datasets)."""
    from gaitshift.errors import InputError

    _, out, _, _ = campaign
    with pytest.raises(InputError, match="--out"):
        Store(out).start(SPEC + "\n# changed\n")
    assert (out / "complete").exists()
