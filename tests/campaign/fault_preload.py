"""A Dask worker preload for the campaign's fault test (not a test module): in every worker process it
wraps :func:`gaitshift.campaign.execute.run_case` so that the first case any worker of the campaign
starts kills its own process (SIGKILL), once per campaign. The marker file named by
:data:`MARKER_ENV` decides the one process that dies (``O_EXCL``) and holds its pid."""

from __future__ import annotations

import os
import signal
from typing import Any

import gaitshift.campaign.execute as execute

MARKER_ENV = "GAITSHIFT_TEST_CAMPAIGN_FAULT"
#: the unwrapped run_case (a worker may load a preload more than once: wrap it once)
ORIGINAL = getattr(execute.run_case, "original", execute.run_case)


def _fault_once() -> None:
    marker = os.environ.get(MARKER_ENV)
    if not marker:
        return
    try:  # O_EXCL: exactly one process of the campaign wins the marker and dies
        fd = os.open(marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
    except FileExistsError:
        return
    os.write(fd, str(os.getpid()).encode())
    os.close(fd)
    os.kill(os.getpid(), signal.SIGKILL)


def run_case(case: dict[str, Any], scenario: Any) -> dict[str, Any]:
    """:func:`gaitshift.campaign.execute.run_case` after the one fault."""
    _fault_once()
    return ORIGINAL(case, scenario)


run_case.original = ORIGINAL  # type: ignore[attr-defined]
execute.run_case = run_case  # the task refers to run_case by its module's name: unpickled, it is this one
