"""Debian's Chromium (``/usr/bin/chromium``, installed by ``.ci/system-deps``), headless and driven by
playwright, for the tests of the browser views (``tests/sim/test_web.py``, ``tests/dds/test_brain_web.py``)."""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator
from typing import Any

CHROMIUM = "/usr/bin/chromium"


@contextlib.contextmanager
def headless_chromium() -> Iterator[Any]:
    """A headless Chromium browser, closed on exit."""
    assert os.access(CHROMIUM, os.X_OK), "Debian's chromium is installed by .ci/system-deps (make test)"
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, headless=True, args=["--no-sandbox"])
        try:
            yield browser
        finally:
            browser.close()


def open_page(browser: Any, url: str) -> Any:
    """The page at ``url`` with its 3D canvas hidden: software WebGL drawing the robot at 60 frames/s would
    take a core from the processes under test on a 2-core machine (the scene's messages still arrive; the
    scene's poses are checked server-side, tests/sim/test_web.py)."""
    page = browser.new_page(viewport={"width": 800, "height": 600})
    page.goto(url)
    page.add_style_tag(content="canvas { display: none !important; }")
    return page
