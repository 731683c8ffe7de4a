"""Shared test set-up: headless MuJoCo rendering, ``tests/`` on the path for the independent checks
of :mod:`physics`, and the in-process CLI runner ``cli``."""

import os
import sys
from pathlib import Path

import pytest

os.environ.setdefault("MUJOCO_GL", "egl")
sys.path.insert(0, str(Path(__file__).parent))


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
