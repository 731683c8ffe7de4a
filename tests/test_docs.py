"""Every Python snippet in the README and in docs/*.md runs: each ```python block is executed in a
fresh namespace in a temporary working directory, so the documentation cannot drift from the code.
A block that fails is reported with its file and its first line."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).parent.parent
BLOCK = re.compile(r"```python\n(.*?)```", re.S)
#: files whose blocks run (the others carry no Python blocks yet, or only blocks listed in SKIPPED)
DOCS = sorted([ROOT / "README.md", *(ROOT / "docs").glob("*.md")])


def snippets() -> list[tuple[str, str]]:
    out = []
    for path in DOCS:
        for i, code in enumerate(BLOCK.findall(path.read_text())):
            out.append((f"{path.relative_to(ROOT)}#{i}", code))
    return out


@pytest.mark.parametrize(("where", "code"), snippets(), ids=[w for w, _ in snippets()])
def test_the_snippet_runs(where, code, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    exec(compile(code, where, "exec"), {"__name__": "__doc_snippet__"})
