"""Shared test set-up: headless MuJoCo rendering, ``tests/`` on the path for the independent checks
of :mod:`physics`, the in-process CLI runner ``cli``, and the scheduling of the suite on pytest-xdist
workers (``-n 2 --dist loadgroup`` in pyproject.toml's addopts).

Under xdist each test file is one unit of work (its module-scoped fixtures are built once, as with
``--dist loadfile``), except that every test that opens a DDS domain (``tests/dds/`` and the
documentation snippets that import ``gaitshift.dds``) goes to one and the same worker: their domain
ids are that process's pid-derived base plus a fixed offset per test (``tests/dds/*.py``,
docs/deploy.md), distinct within one process, so two workers never pick the same domain. The groups
are made here (:func:`pytest_xdist_make_scheduler`) from the node ids, not with ``xdist_group`` marks:
xdist 3.8 passes those by rewriting ``item._nodeid``, which pytest 9.2 no longer reads, so they are
silently ignored (pytest-xdist issue 1386). :func:`_one_dds_worker` fails a DDS test that runs in a
second worker. Any ``--dist`` mode other than loadgroup would spread the DDS tests and is refused."""

import functools
import os
import sys
from pathlib import Path

import pytest

os.environ.setdefault("MUJOCO_GL", "egl")
sys.path.insert(0, str(Path(__file__).parent))

#: the xdist work unit of every test that opens a DDS domain (see the module docstring)
DDS_GROUP = "dds"


@functools.cache
def _dds_snippets() -> set[str]:
    """The ids of the documentation snippets (tests/test_docs.py) that import ``gaitshift.dds``."""
    from test_docs import snippets

    return {where for where, code in snippets() if "gaitshift.dds" in code}


def _opens_dds(nodeid: str, snippets: set[str]) -> bool:
    if nodeid.startswith("tests/dds/"):
        return True
    test, _, param = nodeid.partition("[")
    return test == "tests/test_docs.py::test_the_snippet_runs" and param.rstrip("]") in snippets


def pytest_configure(config):
    """Refuse an xdist run whose ``--dist`` mode could put two DDS tests on two workers at once."""
    dist = config.getoption("dist", "no")
    if getattr(config.option, "numprocesses", None) and dist not in ("no", "loadgroup"):
        raise pytest.UsageError(f"--dist {dist} would spread the DDS tests over workers: use --dist loadgroup")


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_make_scheduler(config, log):
    """``--dist loadgroup``: one work unit per test file, and one for all the DDS tests."""
    if config.getoption("dist") != "loadgroup":
        return None
    from xdist.scheduler import LoadScopeScheduling

    snippets = _dds_snippets()

    class FileOrDDS(LoadScopeScheduling):
        def _split_scope(self, nodeid: str) -> str:
            return DDS_GROUP if _opens_dds(nodeid, snippets) else nodeid.split("::", maxsplit=1)[0]

    return FileOrDDS(config, log)


@pytest.fixture(autouse=True)
def _one_dds_worker(request, tmp_path_factory):
    """Under xdist, a DDS test fails unless its worker is the first one of the session to run one."""
    worker = os.environ.get("PYTEST_XDIST_WORKER")
    if worker is None or not _opens_dds(request.node.nodeid, _dds_snippets()):
        return
    claim = tmp_path_factory.getbasetemp().parent / "dds-worker"  # the session's folder, shared by the workers
    try:
        with open(claim, "x") as f:
            f.write(worker)
    except FileExistsError:
        first = claim.read_text()
        assert first == worker, f"DDS tests ran in {first} and {worker}: their domains may collide (tests/conftest.py)"


class WorkBegan(AssertionError):
    """Raised by :func:`no_work`'s stand-ins: a command began a simulation, an IK solve or a campaign."""


@pytest.fixture
def no_work(monkeypatch):
    """Physics steps, IK solves and Dask clusters raise :class:`WorkBegan`: a command refused "before any
    work" is proved so by what it calls, not by a wall clock."""
    import distributed
    import mink
    import mujoco

    def began(what):
        def stand_in(*args, **kwargs):
            raise WorkBegan(f"{what} was called before the refusal")

        return stand_in

    monkeypatch.setattr(mujoco, "mj_step", began("mujoco.mj_step"))
    monkeypatch.setattr(mink, "solve_ik", began("mink.solve_ik"))
    monkeypatch.setattr(distributed, "LocalCluster", began("distributed.LocalCluster"))
    monkeypatch.setattr(distributed, "Client", began("distributed.Client"))


@pytest.fixture
def cli(capsys):
    """``cli(argv) -> (exit code, stdout, stderr)`` of ``gaitshift argv`` run in-process; any exception
    other than the CLI's SystemExit fails the test (a crash)."""
    from gaitshift.cli import main

    def run(argv: list[str]) -> tuple[int, str, str]:
        capsys.readouterr()
        with pytest.raises(SystemExit) as exc:
            main(argv)
        out, err = capsys.readouterr()
        return int(exc.value.code or 0), out, err

    return run
