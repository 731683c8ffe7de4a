"""The campaign's error contract (issue 28): a spec that expands to more cases than a campaign may hold
is refused before anything is built (it died of MemoryError after 25 s), and a report over a folder
with a damaged part file or a damaged spec is one line, exit 2 (ArrowInvalid and YAML tracebacks)."""

from __future__ import annotations

import shutil
from pathlib import Path

from gaitshift.campaign.cases import MAX_CASES

WALK = Path(__file__).resolve().parents[2] / "docs" / "campaigns" / "g1-walk.yaml"
HUGE = """
name: huge
task: plan
axes:
  scenario: [g1-walk.yaml]
  speed: {start: 0.0, stop: 1.0, step: 0.0001}
  push_impulse: {start: 0.0, stop: 100.0, step: 0.01}
  mass_scale: {start: 0.5, stop: 1.5, step: 0.01}
"""


def test_a_spec_beyond_the_case_limit_is_refused_up_front(cli, tmp_path):
    shutil.copy(WALK, tmp_path / "g1-walk.yaml")
    (tmp_path / "spec.yaml").write_text(HUGE)
    out = tmp_path / "out"
    code, _, err = cli(["campaign", str(tmp_path / "spec.yaml"), "--out", str(out)])
    assert code == 2 and err.count("\n") == 1 and "axes" in err and f"{MAX_CASES:,}" in err
    assert not out.exists()


def test_a_report_over_a_damaged_folder_is_one_line(cli, tmp_path):
    folder = tmp_path / "c"
    (folder / "parts").mkdir(parents=True)
    (folder / "parts" / "0123.parquet").write_bytes(b"not parquet")
    (folder / "spec.yaml").write_text("name: x\ntask: plan\n")
    code, _, err = cli(["campaign", "report", str(folder)])
    assert code == 2 and err.count("\n") == 1 and "part files" in err
    (folder / "parts" / "0123.parquet").unlink()
    (folder / "spec.yaml").write_text(": [")
    code, _, err = cli(["campaign", "report", str(folder)])
    assert code == 2 and err.count("\n") == 1 and "spec" in err
