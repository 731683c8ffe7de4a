"""``--web`` of ``simulate`` and ``teleop --sim``: the browser view (:mod:`gaitshift.sim.web`) around a run."""

from __future__ import annotations

import contextlib
import sys
from collections.abc import Callable, Iterator
from typing import Any

import typer

from gaitshift.cli.app import number


def web_port_option() -> Any:
    """The ``--web-port`` option (one definition for both commands)."""
    return typer.Option(8080, "--web-port", help="With --web: port of the page (the next free one if taken).")


@contextlib.contextmanager
def web_view(enabled: bool, port: int, plan: Callable[[], Any], err: bool = False, **kw: Any) -> Iterator[list[Any]]:
    """The tick hooks of a run: ``[WebView]`` when ``enabled`` (its URL is printed, on stderr when
    ``err``), else ``[]``; the server stops when the block ends. viser's own banner goes to stderr,
    so that ``--json`` keeps stdout for the JSON alone.

    Raises:
        InputError: ``port`` outside 0-65535 (0: any free port).
    """
    number(port, "--web-port", 0, 65535)
    if not enabled:
        yield []
        return
    from gaitshift.sim.web import WebView

    with contextlib.redirect_stdout(sys.stderr):
        view = WebView(plan, port=port, **kw)
    typer.echo(f"web view: {view.url}", err=err)
    try:
        yield [view]
    finally:
        with contextlib.redirect_stdout(sys.stderr):
            view.close()
