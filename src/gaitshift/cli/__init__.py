"""Command-line entry point ``gaitshift``.

The CLI only parses arguments, calls the public API and prints results. Each command module below
registers its commands on :data:`gaitshift.cli.app.app`. User mistakes (:class:`GaitshiftError`,
click usage errors) end with one line on stderr and exit code 2, never a traceback.
"""

from __future__ import annotations

import importlib
import os
import sys
from typing import NoReturn

import typer

try:  # typer >= 0.20 vendors click
    from typer._click import exceptions as _click_exc
except ImportError:  # pragma: no cover - older typer depends on click
    from click import exceptions as _click_exc  # type: ignore[no-redef]

from gaitshift.cli.app import app
from gaitshift.errors import GaitshiftError, InputError

#: Command modules, in help order. Each is ``gaitshift.cli.<name>``.
COMMAND_MODULES = ("core", "vhip", "robot", "sim", "export", "slip", "bench", "campaign", "dds")


def _load_commands() -> None:
    for name in COMMAND_MODULES:
        importlib.import_module(f"{__name__}.{name}")


def _fail(message: str) -> NoReturn:
    """Print ``message`` as one line on stderr and exit with code 2."""
    print("gaitshift: error: " + " ".join(message.split()), file=sys.stderr)
    sys.exit(2)


def _flag_value(flag: str, argv: list[str]) -> str | None:
    """The text given to ``flag`` on the command line (``--flag value`` or ``--flag=value``)."""
    for i, arg in enumerate(argv):
        if arg == flag and i + 1 < len(argv):
            return argv[i + 1]
        if arg.startswith(flag + "="):
            return arg[len(flag) + 1 :]
    return None


def _usage_message(exc: _click_exc.UsageError, argv: list[str]) -> str:
    """Click's message, or for a flag whose text does not convert (``--height abc``) the house form
    ``<flag> = <value> is invalid: allowed <what the type allows>``."""
    param = getattr(exc, "param", None)
    if type(exc) is _click_exc.BadParameter and param is not None and getattr(param, "opts", None):
        flag = max(param.opts, key=len)
        value = next((v for v in (_flag_value(o, argv) for o in param.opts) if v is not None), None)
        if value is not None:
            allowed = exc.message.removeprefix("Input should be ")
            return str(InputError(flag, value, allowed))
    return exc.format_message()


def main(argv: list[str] | None = None) -> None:
    """Run the CLI; exit 2 with a one-line message on bad input."""
    os.environ.setdefault("MUJOCO_GL", "egl")  # headless rendering; must precede any mujoco import
    _load_commands()
    try:
        rv = app(args=argv, standalone_mode=False, prog_name="gaitshift")
    except GaitshiftError as exc:
        _fail(str(exc))
    except _click_exc.NoArgsIsHelpError:  # `gaitshift` alone: the help was printed
        sys.exit(0)
    except _click_exc.UsageError as exc:
        _fail(_usage_message(exc, sys.argv[1:] if argv is None else argv))
    except typer.Abort as exc:
        if isinstance(exc.__cause__, EOFError):  # click turns a stray EOFError into Abort: a bug, show it
            raise exc.__cause__ from None
        sys.exit(130)  # Ctrl-C
    except typer.Exit as exc:
        sys.exit(exc.exit_code)
    except BrokenPipeError:  # e.g. `gaitshift plan ... | head -1`
        sys.stderr.close()
        sys.exit(0)
    sys.exit(rv if isinstance(rv, int) else 0)
