"""The background re-planner's worker side (:mod:`gaitshift.control.replanner` is the host's): the driver,
the requests it takes in tick order, and the answers it gives.

A request is a tag and up to seven float64 (:data:`TICK`: t s, com (3,) m, com_vel (3,) m/s;
:data:`COMMAND`: vx m/s, vy m/s, yaw_rate rad/s; :data:`GOTO`: x m, y m, yaw rad; :data:`STOP`,
:data:`QUIT`: none; :data:`FREE`: the number of the oldest plan file the host may still map;
:data:`MAP`: the map a perceiving driver reads from now on, a copy of the controller's made by the host at
one of the driver's ``map_instants``: by reference in a thread, the number of its file in a process). On a
process's pipe it is a fixed record of :data:`REQUEST_BYTES`. An answer is a new plan (and its samples,
the driver's re-plan count, the number of the tick request that made it), an error, or a perceiving
driver's new count of re-plans not taken (``refused``); on a process's pipe a record of
:data:`RESULT_BYTES` (tag ``P``, ``E`` or ``R``, 3 int64), the plan or error in a file.
"""

from __future__ import annotations

import contextlib
import os
import pickle
import queue
import signal
import struct
import time
from collections.abc import Iterator
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.control.plan_files import PlanFolder
from gaitshift.control.plan_samples import PlanSamples
from gaitshift.errors import GaitshiftError
from gaitshift.trajectory.contract import Trajectory

__all__ = [
    "COMMAND",
    "FREE",
    "GOTO",
    "MAP",
    "PLANNER_NICE",
    "PLANNER_POLL",
    "QUIT",
    "RESULT_BYTES",
    "STOP",
    "TICK",
    "Update",
    "Worker",
    "map_folder",
    "record",
    "serve_process",
    "serve_thread",
]

#: a new plan and its samples
Update = tuple[Trajectory, PlanSamples]
#: the requests' tags (module docstring)
TICK, COMMAND, GOTO, STOP, QUIT, FREE, MAP = b"T", b"C", b"G", b"S", b"Q", b"F", b"M"
#: bytes of a request record (tag, 7 float64) and of a result record (tag, 3 int64)
REQUEST_BYTES, RESULT_BYTES = 57, 25
#: the worker process's niceness: it takes the cores the ticks leave (a re-plan waits rather than a tick)
PLANNER_NICE = 10
#: s between two looks of the worker process for requests (it adds up to this much to a plan's lag)
PLANNER_POLL = 0.002


class Worker:
    """The worker's side: the driver, and what a request does to it."""

    def __init__(self, driver: Any, sole_length: float) -> None:
        self.driver, self.sole_length = driver, sole_length
        self.ticks = 0  # tick requests handled
        self.refused = getattr(driver, "refused", None)  # a perceiving driver's re-plans not taken

    def handle(self, tag: bytes, v: tuple[Any, ...]) -> tuple[Update, int, int] | None:
        """Apply one request; a new plan and its samples, the driver's re-plan count and the number of the
        tick request that made it (1: the first), or None."""
        d = self.driver
        if tag == TICK:
            self.ticks += 1
            new = d.maybe_replan(v[0], np.array(v[1:4]), np.array(v[4:7]))
            if new is None:
                return None
            return (new, PlanSamples.from_trajectory(new, self.sole_length)), int(d.replans), self.ticks
        if tag == COMMAND:
            d.command(*v[:3])
        elif tag == GOTO:
            d.gen.goto(*v[:3])
        elif tag == STOP:
            d.stop()
        elif tag == MAP:
            d.see(v[0])
        return None

    def new_refusals(self) -> int | None:
        """The driver's count of re-plans not taken, when it changed since the last call; else None."""
        now = getattr(self.driver, "refused", None)
        if now is None or now == self.refused:
            return None
        self.refused = now
        return int(now)


def record(tag: bytes, values: tuple[float, ...]) -> bytes:
    """A request as a fixed-size record: the tag and seven float64 (padded with zeros)."""
    return tag + struct.pack("<7d", *values, *(0.0,) * (7 - len(values)))


def map_folder(folder: Path) -> PlanFolder:
    """The files of the maps the host hands a process worker: a subfolder of its private folder."""
    (Path(folder) / "maps").mkdir(exist_ok=True)
    return PlanFolder(Path(folder) / "maps")


def _requests(fd: int) -> Iterator[tuple[bytes, tuple[float, ...]]]:
    """The requests on the pipe ``fd``, in order, until its end. The pipe is polled every
    :data:`PLANNER_POLL` s rather than waited on: a writer to a pipe someone waits on wakes it, which costs
    the tick that writes (0.09 ms per tick measured on this machine's virtual cores)."""
    os.set_blocking(fd, False)
    buf = b""
    while True:
        try:
            chunk = os.read(fd, REQUEST_BYTES * 1024)
        except BlockingIOError:
            time.sleep(PLANNER_POLL)
            continue
        if not chunk:
            return
        buf += chunk
        whole = len(buf) - len(buf) % REQUEST_BYTES
        for k in range(0, whole, REQUEST_BYTES):
            yield buf[k : k + 1], struct.unpack("<7d", buf[k + 1 : k + REQUEST_BYTES])
        buf = buf[whole:]


def serve_process(requests: Connection, results: Connection, payload: str, sole_length: float) -> None:
    """The worker process (niced by :data:`PLANNER_NICE`): the driver from the pickle file ``payload``;
    requests as fixed records on ``requests``; each new plan (or error) as file ``n`` of the payload's folder
    (:class:`~gaitshift.control.plan_files.PlanFolder`, freed when the host says so), then announced on
    ``results`` as the record (tag, n, re-plans, tick): the tick never waits for the worker. A map request's
    file (:func:`map_folder`) is read mapped and the older ones removed."""
    files, maps = PlanFolder(Path(payload).parent), map_folder(Path(payload).parent)
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # a ^C is the host's to handle; the worker ends with its pipe
    with contextlib.suppress(OSError, AttributeError):
        os.nice(PLANNER_NICE)
    worker = Worker(pickle.loads(Path(payload).read_bytes()), sole_length)
    n = 0
    for tag, numbers in _requests(requests.fileno()):
        if tag == QUIT:
            return
        if tag == FREE:  # removed here: freeing a mapped file's pages is the worker's time, not the tick's
            files.free_before(int(numbers[0]))
            continue
        values: tuple[Any, ...] = numbers
        if tag == MAP:  # the driver lets the older map go: its file can go
            values = (maps.read(int(numbers[0])),)
            maps.free_before(int(numbers[0]))
        try:
            out: Any = worker.handle(tag, values)
        except Exception as e:  # handed to the controller, raised by its next tick (one picklable type)
            out = (GaitshiftError(str(e) if isinstance(e, GaitshiftError) else f"planner: {e!r}"), 0, worker.ticks)
        refused = worker.new_refusals()
        if refused is not None:
            os.write(results.fileno(), b"R" + struct.pack("<3q", refused, 0, worker.ticks))
        if out is None:
            continue
        n += 1
        files.write(n, out[0])
        kind = b"E" if isinstance(out[0], Exception) else b"P"
        os.write(results.fileno(), kind + struct.pack("<3q", n, out[1], out[2]))


def serve_thread(worker: Worker, requests: queue.SimpleQueue[Any], results: queue.SimpleQueue[Any]) -> None:
    """The worker thread: requests in order until the quit request; plans (by reference), errors and new
    refusal counts out."""
    while True:
        tag, values = requests.get()
        if tag == QUIT:
            return
        try:
            out = worker.handle(tag, values)
        except Exception as e:  # handed to the controller, raised by its next tick
            results.put(("error", e))
            continue
        refused = worker.new_refusals()
        if refused is not None:
            results.put(("refused", refused))
        if out is not None:
            results.put(("plan", *out))
