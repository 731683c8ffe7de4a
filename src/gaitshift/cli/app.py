"""The typer application that every ``gaitshift.cli.*`` command module registers on, and the checks
its commands run on their flags before doing any work (one :class:`InputError` naming the flag)."""

from __future__ import annotations

import contextlib
import math
import tempfile
from collections.abc import Iterator
from pathlib import Path

import typer

from gaitshift.common.atomic import check_name, check_suffix
from gaitshift.errors import InputError

app = typer.Typer(
    name="gaitshift",
    help="Walking, running and walk-run transitions for biped robots.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


def out_file(path: Path, flag: str, suffixes: tuple[str, ...]) -> Path:
    """Check an output file flag before any work: one of ``suffixes``, not an existing folder or
    special file, and a location where a file can be created.

    Raises:
        InputError: naming ``flag``, the path and what is allowed.
    """
    check_suffix(path, flag, suffixes)
    check_name(path, flag)
    if path.exists() and not path.is_file():
        raise InputError(flag, str(path), "a file path (this is a folder or a special file)")
    _writable(path.parent, path, flag)
    return path


def out_folder(path: Path, flag: str) -> Path:
    """Check an output folder flag before any work: a folder, or a path where one can be created.

    Raises:
        InputError: naming ``flag``, the path and what is allowed.
    """
    check_name(path / "x", flag)  # the folder's own name and the path, with room for the files inside
    if path.exists() and not path.is_dir():
        raise InputError(flag, str(path), "a folder (it is created if missing); this is a file")
    _writable(path, path, flag)
    return path


def _writable(folder: Path, path: Path, flag: str) -> None:
    """A file can be created in ``folder``, or in its nearest existing ancestor (which must be a
    folder); probed with a temporary file that is removed at once."""
    base = folder.absolute()
    while not base.exists() and base != base.parent:
        base = base.parent
    if not base.is_dir():
        raise InputError(flag, str(path), f"a path whose parent {base} is a folder, not a file")
    try:
        with tempfile.TemporaryFile(dir=base):
            pass
    except OSError as exc:
        raise InputError(flag, str(path), f"a writable location ({base}: {exc.strerror})") from None


def number(value: float, flag: str, low: float, high: float, *, open_low: bool = False) -> float:
    """Check a numeric flag: finite and in [low, high] (``(low, high]`` with ``open_low``).

    Raises:
        InputError: naming ``flag``, the value and the range.
    """
    ok = math.isfinite(value) and (low < value if open_low else low <= value) and value <= high
    if not ok:
        raise InputError(flag, value, f"a number in {'(' if open_low else '['}{low:g}, {high:g}]")
    return value


@contextlib.contextmanager
def flags_named(flags: dict[str, str]) -> Iterator[None]:
    """Re-raise an :class:`InputError` whose field is a library argument (``step_width``) under the
    command-line flag it came from (``--step-width``), keeping the value and what is allowed; the
    library stays the one source of the allowed range."""
    try:
        yield
    except InputError as exc:
        if exc.field not in flags:
            raise
        raise InputError(flags[exc.field], exc.value, exc.allowed) from None
