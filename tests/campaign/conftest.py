"""Shared set-up of the campaign tests: the CLI runner of tests/cli."""

import pytest

from gaitshift.cli import main


@pytest.fixture
def cli(capsys):
    """``cli(argv) -> (exit code, stdout, stderr)`` of ``gaitshift argv`` run in-process."""

    def run(argv: list[str]) -> tuple[int, str, str]:
        capsys.readouterr()
        with pytest.raises(SystemExit) as exc:
            main(argv)
        out, err = capsys.readouterr()
        return int(exc.value.code or 0), out, err

    return run
