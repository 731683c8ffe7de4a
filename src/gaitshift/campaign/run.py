"""Running a campaign on Dask (``dask.distributed``): a local cluster or an existing scheduler.

* Cluster: a ``LocalCluster`` of ``workers`` single-threaded worker PROCESSES (default: every core),
  or, with ``scheduler``, the cluster behind that address (``tcp://host:8786``; ``dask scheduler`` +
  ``dask worker``, or dask-jobqueue on SLURM, docs/robustness.md). The dashboard link is printed.
* Tasks: one per case not yet in the store, ``run_case(case, scenario)``: the case is a plain dict and
  the scenario a validated pydantic object; the task returns plain dicts and numpy arrays, so no MuJoCo
  object ever crosses a process boundary. A worker that dies takes its case with it; the scheduler
  re-runs that case on another worker (``distributed.scheduler.allowed-failures`` times, then the case
  is reported as lost and stays to do for the next run).
* Results: written by this (client) process as they arrive (:mod:`gaitshift.campaign.store`), so
  the workers need no shared disk. The ``complete`` marker is written only when every case has a row.
"""

from __future__ import annotations

import contextlib
import math
import sys
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from gaitshift.campaign.cases import expand
from gaitshift.campaign.execute import run_case
from gaitshift.campaign.spec import CampaignSpec
from gaitshift.campaign.store import Store
from gaitshift.errors import InputError

__all__ = ["CampaignSummary", "cluster_client", "run_campaign"]

#: seconds to wait for a scheduler given by address
CONNECT_TIMEOUT = 10.0


@dataclass(frozen=True)
class CampaignSummary:
    """What a run did: cases in the spec, skipped (already done), run now, lost (no row), complete."""

    cases: int
    skipped: int
    ran: int
    lost: int
    complete: bool
    wall_time: float


@contextlib.contextmanager
def cluster_client(scheduler: str | None, workers: int | None) -> Iterator[Any]:
    """A ``distributed.Client`` of the scheduler at ``scheduler``, or of a new ``LocalCluster`` of
    ``workers`` one-thread processes (None: every core); both are closed on exit.

    Raises:
        InputError: ``--scheduler`` cannot be reached, or ``--workers`` < 1.
    """
    import dask
    from distributed import Client, LocalCluster

    if scheduler is not None:
        _reachable(scheduler)
        try:
            with dask.config.set({"distributed.comm.timeouts.connect": f"{CONNECT_TIMEOUT}s"}):
                client = Client(scheduler, timeout=f"{CONNECT_TIMEOUT}s")  # type: ignore[no-untyped-call]
        except (OSError, TimeoutError, ValueError) as exc:
            msg = " ".join(str(exc).split())[:160]
            raise InputError("--scheduler", scheduler, f"the address of a running Dask scheduler ({msg})") from None
        with client:
            yield client
        return
    import os

    n = workers if workers is not None else os.cpu_count() or 1
    if n < 1:
        raise InputError("--workers", n, "an integer >= 1")
    with (
        LocalCluster(  # type: ignore[no-untyped-call]
            n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0"
        ) as cluster,
        Client(cluster) as client,  # type: ignore[no-untyped-call]
    ):
        yield client


def _reachable(address: str) -> None:
    """Fail fast when nothing listens at a ``tcp://host:port`` (or ``host:port``) address: a refused
    connection is an error at once, not after the client's connect timeout."""
    import socket
    from urllib.parse import urlsplit

    if "://" in address and not address.startswith("tcp://"):
        return  # tls://, ucx://, inproc://: left to the client
    parts = urlsplit(address if "://" in address else "tcp://" + address)
    try:
        host, port = parts.hostname, parts.port
    except ValueError as exc:
        raise InputError("--scheduler", address, f"an address tcp://HOST:PORT ({exc})") from None
    if not host or port is None:
        raise InputError("--scheduler", address, "an address tcp://HOST:PORT")
    try:
        with socket.create_connection((host, port), timeout=CONNECT_TIMEOUT):
            pass
    except OSError as exc:
        why = exc.strerror or type(exc).__name__
        raise InputError("--scheduler", address, f"the address of a running Dask scheduler ({why})") from None


def _bar(done: int, total: int, width: int = 30) -> str:
    frac = done / total if total else 1.0
    fill = math.floor(frac * width)
    return f"[{'#' * fill}{'.' * (width - fill)}] {done}/{total}"


def _scenarios(spec: CampaignSpec, cases: list[dict[str, Any]]) -> dict[str, Any]:
    from gaitshift.scenario import load_scenario

    return {name: load_scenario(spec.scenario_path(name)) for name in {c["scenario"] for c in cases}}


def run_campaign(
    spec: CampaignSpec,
    spec_text: str,
    out: str | Path,
    scheduler: str | None = None,
    workers: int | None = None,
    echo: Callable[[str], None] | None = None,
) -> CampaignSummary:
    """Run every case of ``spec`` that ``out`` does not hold yet (module docstring).

    ``spec_text`` is recorded as ``out/spec.yaml``; ``echo`` receives the dashboard link and the
    progress lines (None: a bar on stderr).

    Raises:
        InputError: a bad spec (before anything is written), a folder of another campaign, or an
            unreachable scheduler.
    """
    import time

    from distributed import as_completed

    cases = expand(spec)
    scenarios = _scenarios(spec, cases)
    store = Store(out)
    store.check(spec_text)
    done = store.done()
    # in hash order: a pseudo-random order, so that a partial run covers the whole grid evenly
    todo = sorted((c for c in cases if c["case_hash"] not in done), key=lambda c: c["case_hash"])
    say = echo or _stderr_bar
    wall0 = time.perf_counter()
    ran = lost = 0
    with contextlib.ExitStack() as stack:
        # no cluster when nothing is left to run; an unreachable scheduler fails before any write
        client = stack.enter_context(cluster_client(scheduler, workers)) if todo else None
        store.start(spec_text)
        if client is not None:
            say(f"dashboard: {client.dashboard_link}")
        say(f"{len(cases)} cases, {len(cases) - len(todo)} already done, {len(todo)} to run")
        futures = [
            client.submit(run_case, c, scenarios[c["scenario"]], key=f"case-{c['case_hash']}", pure=False)
            for c in todo
            if client is not None
        ]
        for fut in as_completed(futures) if futures else ():  # type: ignore[no-untyped-call]
            try:
                store.write(fut.result())
                ran += 1
            except Exception as exc:  # a lost worker beyond the retries, or a bug in one case
                lost += 1
                say(f"case {fut.key} lost: {type(exc).__name__}: {' '.join(str(exc).split())[:200]}")
            say(_bar(ran + lost, len(todo)))
        complete = store.finish({c["case_hash"] for c in cases})
    if echo is None:
        sys.stderr.write("\n")
    return CampaignSummary(len(cases), len(cases) - len(todo), ran, lost, complete, time.perf_counter() - wall0)


def _stderr_bar(line: str) -> None:
    """Progress bars overwrite themselves on a terminal; other lines end with a newline."""
    if line.startswith("["):
        sys.stderr.write("\r" + line)
    else:
        sys.stderr.write(line + "\n")
    sys.stderr.flush()
