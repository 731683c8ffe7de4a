"""Every Python snippet in the README and in docs/*.md runs: each ```python block is executed in a
fresh namespace in a temporary working directory (with ``docs/`` reachable there, as from the
repository's root), so the documentation cannot drift from the code. The only block not run is listed
in :data:`NOT_HERE` with the reason this machine cannot run it."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).parent.parent
BLOCK = re.compile(r"```python\n(.*?)```", re.S)
#: files whose blocks run (the others carry no Python blocks yet, or only blocks listed in SKIPPED)
DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


#: blocks this machine cannot run, and why
NOT_HERE = {
    "docs/robustness.md#1": "starts a SLURM cluster (dask-jobqueue on a login node); there is no SLURM here",
}


def snippets() -> list[tuple[str, str]]:
    out = []
    for path in DOCS:
        for i, code in enumerate(BLOCK.findall(path.read_text())):
            out.append((f"{path.relative_to(ROOT)}#{i}", code))
    return out


@pytest.mark.parametrize(("where", "code"), snippets(), ids=[w for w, _ in snippets()])
def test_the_snippet_runs(where, code, tmp_path, monkeypatch):
    if where in NOT_HERE:
        pytest.skip(NOT_HERE[where])
    (tmp_path / "docs").symlink_to(ROOT / "docs")
    monkeypatch.chdir(tmp_path)
    exec(compile(code, where, "exec"), {"__name__": "__doc_snippet__"})
