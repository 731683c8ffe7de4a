"""Every package that pyproject.toml declares (``[project] dependencies`` and everything the ``all``
extra pulls in) is installed at a version its specifier allows and imports: a missing or broken
dependency is a test failure, never a skip."""

from __future__ import annotations

import importlib
import importlib.metadata as md
import re
import tomllib
from pathlib import Path

import pytest
from packaging.requirements import Requirement

PYPROJECT = Path(__file__).resolve().parents[1] / "pyproject.toml"


def _normal(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def declared(project: dict, extra: str = "all") -> list[Requirement]:
    """The requirements of ``[project] dependencies`` plus ``extra``, with self-references such as
    ``gaitshift[robot,test]`` expanded."""
    extras = project.get("optional-dependencies", {})
    out = [Requirement(r) for r in project.get("dependencies", [])]
    todo, seen = [extra], set()
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        seen.add(name)
        for text in extras.get(name, []):
            req = Requirement(text)
            if _normal(req.name) == _normal(project["name"]):
                todo.extend(sorted(req.extras, reverse=True))  # a set: the same order in every process (xdist)
            else:
                out.append(req)
    return out


PROJECT = tomllib.loads(PYPROJECT.read_text())["project"]
REQUIREMENTS = declared(PROJECT)
#: distribution (normalised) -> the top-level modules it installs
MODULES: dict[str, list[str]] = {}
for _module, _dists in md.packages_distributions().items():
    for _dist in _dists:
        MODULES.setdefault(_normal(_dist), []).append(_module)


def test_the_all_extra_covers_every_optional_group():
    names = {_normal(r.name) for r in REQUIREMENTS}
    for group, reqs in PROJECT["optional-dependencies"].items():
        if group != "all":
            assert {_normal(Requirement(r).name) for r in reqs} <= names, group
    assert {"numpy", "mujoco", "casadi", "hypothesis", "mypy"} <= names


@pytest.mark.parametrize("req", REQUIREMENTS, ids=str)
def test_declared_dependency_is_installed_and_imports(req):
    try:
        version = md.version(req.name)
    except md.PackageNotFoundError:
        pytest.fail(f"{req.name} is declared in pyproject.toml but not installed")
    assert req.specifier.contains(version, prereleases=True), f"{req.name} {version} does not satisfy {req}"
    modules = sorted(m for m in MODULES.get(_normal(req.name), []) if m.isidentifier() and not m.startswith("_"))
    if not modules:  # a stub-only distribution (types-*) installs <package>-stubs and nothing to import
        assert any(m.endswith("-stubs") for m in MODULES.get(_normal(req.name), [])), req.name
        return
    for module in modules:
        importlib.import_module(module)


def test_a_missing_dependency_is_reported_not_skipped():
    """The check itself: an unknown distribution raises PackageNotFoundError (so the test above fails)."""
    with pytest.raises(md.PackageNotFoundError):
        md.version("gaitshift-no-such-distribution")
    reqs = declared({"name": "p", "dependencies": ["a"], "optional-dependencies": {"x": ["b"], "all": ["p[x]"]}})
    assert [r.name for r in reqs] == ["a", "b"]
