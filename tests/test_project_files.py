"""The project's metadata files agree with each other: LICENSE is the MIT text that pyproject.toml
declares (SPDX ``MIT`` with ``license-files``), CITATION.cff is valid YAML with the CFF 1.2.0 keys
and cites the software and both papers, and CHANGELOG.md keeps an Unreleased section."""

from __future__ import annotations

import tomllib
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]


def test_license_file_is_the_mit_licence_pyproject_declares():
    text = (ROOT / "LICENSE").read_text()
    assert PROJECT["license"] == "MIT"
    assert PROJECT["license-files"] == ["LICENSE"]
    assert text.startswith("MIT License\n")
    assert "Copyright (c) 2026 The gaitshift developers" in text
    assert 'THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND' in text


def test_citation_cff_has_the_required_keys_and_both_papers():
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    assert cff["cff-version"] == "1.2.0"
    for key in ("message", "title", "authors", "type", "license", "version", "references"):
        assert cff[key], key
    assert cff["type"] == "software" and cff["license"] == PROJECT["license"]
    assert str(cff["version"]) == PROJECT["version"]
    refs = cff["references"]
    assert len(refs) == 2
    for ref in refs:
        assert ref["type"] and ref["title"] and ref["authors"]
        assert all("family-names" in a and "given-names" in a for a in ref["authors"])
    titles = " ".join(r["title"] for r in refs)
    assert "Time-Varying Linear Inverted Pendulum Mode" in titles and "Smooth State Switching" in titles
    assert refs[1]["doi"] == "10.3390/biomimetics8010114"


def test_changelog_has_an_unreleased_section_before_the_releases():
    text = (ROOT / "CHANGELOG.md").read_text()
    assert text.index("## [Unreleased]") < text.index(f"## [{PROJECT['version']}]")
