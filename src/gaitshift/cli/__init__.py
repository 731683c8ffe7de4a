"""Command-line entry point ``gaitshift``.

The CLI only parses arguments, calls the public API and prints results. Each command module below
registers its commands on :data:`gaitshift.cli.app.app`. User mistakes (:class:`GaitshiftError`,
click usage errors) end with one line on stderr and exit code 2, never a traceback.
"""

from __future__ import annotations

import importlib
import os
import sys

import typer

try:  # typer >= 0.20 vendors click
    from typer._click import exceptions as _click_exc
except ImportError:  # pragma: no cover - older typer depends on click
    from click import exceptions as _click_exc

from ..errors import GaitshiftError
from .app import app

#: Command modules, in help order. Each is ``gaitshift.cli.<name>``.
COMMAND_MODULES = ("core", "online", "robot", "sim", "slip", "bench")


def _load_commands() -> None:
    for name in COMMAND_MODULES:
        module = f"{__name__}.{name}"
        try:
            importlib.import_module(module)
        except ModuleNotFoundError as exc:  # a command module not written yet
            if exc.name != module:
                raise


def main(argv: list[str] | None = None) -> None:
    """Run the CLI; exit 2 with a one-line message on bad input."""
    os.environ.setdefault("MUJOCO_GL", "egl")  # headless rendering; must precede any mujoco import
    _load_commands()
    try:
        rv = app(args=argv, standalone_mode=False, prog_name="gaitshift")
    except GaitshiftError as exc:
        print(f"gaitshift: error: {exc}", file=sys.stderr)
        sys.exit(2)
    except _click_exc.UsageError as exc:
        msg = exc.format_message().replace("\n", " ")
        print(f"gaitshift: error: {msg}", file=sys.stderr)
        sys.exit(2)
    except typer.Abort:
        sys.exit(1)
    except typer.Exit as exc:
        sys.exit(exc.exit_code)
    except BrokenPipeError:  # e.g. `gaitshift plan ... | head -1`
        sys.stderr.close()
        sys.exit(0)
    sys.exit(rv if isinstance(rv, int) else 0)
