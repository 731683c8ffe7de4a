"""Where the plan driver re-plans: inside the tick ("inline") or in a background worker ("thread",
"process"), so that a planning instant does not make the tick miss its period.

Every tick the controller hands the driver (:mod:`gaitshift.control.drivers`) the plan time ``t`` s and
the measured CoM position (3,) m and velocity (3,) m/s; at a planning instant the driver re-plans
(6-30 ms on a 2-core machine, 3-15 control periods of 2 ms).

* ``inline``: ``driver.maybe_replan`` runs in the tick, and the new plan is tracked from that very tick.
  Deterministic: in-process simulations use it.
* ``thread`` and ``process``: a worker owns the driver. Each tick sends it ``(t, com, com_vel)`` and
  returns at once; the worker calls ``maybe_replan`` with exactly these arguments, in tick order (live
  commands in between, in the order given), and derives the new plan's
  :class:`~gaitshift.control.plan_samples.PlanSamples`. A tick takes, at its start, every plan the
  worker has finished since the last tick (in order) and tracks the newest; until then it tracks the
  current plan. The worker computes what the inline mode computes: the plan of the state of the instant
  the re-plan was due.

**Latency added**: a plan due at tick ``k`` is tracked from tick ``k + m`` instead of tick ``k``, ``m >= 1``
the ticks that started while the worker computed it (its compute time, its wait for a core, and in a
process up to :data:`PLANNER_POLL` s before it looks at the request): :attr:`BackgroundReplan.lags` holds
``m`` per plan. The plans are indexed by plan time, so a plan that arrives late is tracked from the sample
of the tick it arrives at, as it would have been inline; ticks ``k .. k + m - 1`` track the previous plan
(the locomotion driver's look-ahead only extends it there; a VHIP re-plan's new footholds take effect ``m``
ticks later). A background run depends on the worker's timing: it is not deterministic.

``thread`` shares the interpreter lock with the ticks (``sys.setswitchinterval`` is lowered to
:data:`SWITCH_INTERVAL` s for the whole process so that a tick waits less for it); ``process`` runs the
driver in a spawned process (its own interpreter, niced by :data:`PLANNER_NICE`; the plan comes back in a
file of a private folder, its arrays mapped rather than copied, :mod:`gaitshift.control.plan_files`, so
the tick never waits for the worker to write it nor reads the whole plan): the one for real time. A
program that builds a "process" controller must guard its main module (``if __name__ == "__main__":``), as
any program that spawns processes; an error of the worker's driver is raised by the next tick as a
:class:`~gaitshift.errors.GaitshiftError` with its message.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import pickle
import queue
import shutil
import signal
import struct
import sys
import tempfile
import threading
import time
import weakref
from collections.abc import Iterator
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.control.drivers import PlanDriver
from gaitshift.control.plan_files import PlanFolder
from gaitshift.control.plan_samples import PlanSamples
from gaitshift.errors import GaitshiftError, InputError
from gaitshift.trajectory.contract import Trajectory

__all__ = [
    "PLANNER_NICE",
    "PLANNER_POLL",
    "REPLAN_MODES",
    "SWITCH_INTERVAL",
    "BackgroundReplan",
    "InlineReplan",
    "Update",
    "replanner",
]

#: where the driver re-plans (module docstring)
REPLAN_MODES = ("inline", "thread", "process")
#: s, the interpreter's switch interval in the "thread" mode (Python's default: 0.005 s)
SWITCH_INTERVAL = 2e-4
#: a new plan and its samples
Update = tuple[Trajectory, PlanSamples]

#: a request to the worker: a tag and its values (tick: t s, com (3,) m, com_vel (3,) m/s; command: vx m/s,
#: vy m/s, yaw_rate rad/s; goto: x m, y m, yaw rad; stop, quit: none; free: the number of the oldest plan
#: file the host may still map), padded with zeros to seven float64 on the process's pipe
_TICK, _COMMAND, _GOTO, _STOP, _QUIT, _FREE = b"T", b"C", b"G", b"S", b"Q", b"F"
#: bytes of a request record (tag, 7 float64) and of a result record (tag "P" or "E", 3 int64)
_REQUEST, _RESULT = 57, 25
#: the worker process's niceness: it takes the cores the ticks leave (a re-plan waits rather than a tick)
PLANNER_NICE = 10
#: s between two looks of the worker process for requests (it adds up to this much to a plan's lag)
PLANNER_POLL = 0.002


class InlineReplan:
    """The driver called in the tick (module docstring, "inline").

    Args:
        driver: the plan driver. sole_length: m, the robot's sole length (:meth:`PlanSamples.from_trajectory`).
    """

    def __init__(self, driver: PlanDriver, sole_length: float) -> None:
        self.driver, self.sole_length = driver, sole_length

    def step(self, t: float, com: np.ndarray, com_vel: np.ndarray) -> list[Update]:
        """The driver at plan time ``t`` s with the measured CoM ((3,) m, (3,) m/s): its new plan, if any."""
        new = self.driver.maybe_replan(t, com, com_vel)
        return [] if new is None else [(new, PlanSamples.from_trajectory(new, self.sole_length))]

    def close(self) -> None:
        """Nothing to stop."""


class _Worker:
    """The worker's side: the driver, and what a request does to it."""

    def __init__(self, driver: Any, sole_length: float) -> None:
        self.driver, self.sole_length = driver, sole_length
        self.ticks = 0  # tick requests handled

    def handle(self, tag: bytes, v: tuple[float, ...]) -> tuple[Update, int, int] | None:
        """Apply one request; a new plan and its samples, the driver's re-plan count and the number of the
        tick request that made it (1: the first), or None."""
        d = self.driver
        if tag == _TICK:
            self.ticks += 1
            new = d.maybe_replan(v[0], np.array(v[1:4]), np.array(v[4:7]))
            if new is None:
                return None
            return (new, PlanSamples.from_trajectory(new, self.sole_length)), int(d.replans), self.ticks
        if tag == _COMMAND:
            d.command(*v[:3])
        elif tag == _GOTO:
            d.gen.goto(*v[:3])
        elif tag == _STOP:
            d.stop()
        return None


def _record(tag: bytes, values: tuple[float, ...]) -> bytes:
    """A request as a fixed-size record: the tag and seven float64 (padded with zeros)."""
    return tag + struct.pack("<7d", *values, *(0.0,) * (7 - len(values)))


def _requests(fd: int) -> Iterator[tuple[bytes, tuple[float, ...]]]:
    """The requests on the pipe ``fd``, in order, until its end. The pipe is polled every
    :data:`PLANNER_POLL` s rather than waited on: a writer to a pipe someone waits on wakes it, which costs
    the tick that writes (0.09 ms per tick measured on this machine's virtual cores)."""
    os.set_blocking(fd, False)
    buf = b""
    while True:
        try:
            chunk = os.read(fd, _REQUEST * 1024)
        except BlockingIOError:
            time.sleep(PLANNER_POLL)
            continue
        if not chunk:
            return
        buf += chunk
        whole = len(buf) - len(buf) % _REQUEST
        for k in range(0, whole, _REQUEST):
            yield buf[k : k + 1], struct.unpack("<7d", buf[k + 1 : k + _REQUEST])
        buf = buf[whole:]


def _serve_process(requests: Connection, results: Connection, payload: str, sole_length: float) -> None:
    """The worker process (niced by :data:`PLANNER_NICE`): the driver from the pickle file ``payload``;
    requests as fixed records on ``requests``; each new plan (or error) as file ``n`` of the payload's folder
    (:class:`~gaitshift.control.plan_files.PlanFolder`, freed when the host says so), then announced on
    ``results`` as the record (tag, n, re-plans, tick): the tick never waits for the worker."""
    files = PlanFolder(Path(payload).parent)
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # a ^C is the host's to handle; the worker ends with its pipe
    with contextlib.suppress(OSError, AttributeError):
        os.nice(PLANNER_NICE)
    worker = _Worker(pickle.loads(Path(payload).read_bytes()), sole_length)
    n = 0
    for tag, values in _requests(requests.fileno()):
        if tag == _QUIT:
            return
        if tag == _FREE:  # removed here: freeing a mapped file's pages is the worker's time, not the tick's
            files.free_before(int(values[0]))
            continue
        try:
            out: Any = worker.handle(tag, values)
        except Exception as e:  # handed to the controller, raised by its next tick (one picklable type)
            out = (GaitshiftError(str(e) if isinstance(e, GaitshiftError) else f"planner: {e!r}"), 0, worker.ticks)
        if out is None:
            continue
        n += 1
        files.write(n, out[0])
        kind = b"E" if isinstance(out[0], Exception) else b"P"
        os.write(results.fileno(), kind + struct.pack("<3q", n, out[1], out[2]))


def _serve_thread(worker: _Worker, requests: queue.SimpleQueue[Any], results: queue.SimpleQueue[Any]) -> None:
    """The worker thread: requests in order until the quit request; plans (by reference) and errors out."""
    while True:
        tag, values = requests.get()
        if tag == _QUIT:
            return
        try:
            out = worker.handle(tag, values)
        except Exception as e:  # handed to the controller, raised by its next tick
            results.put(("error", e))
            continue
        if out is not None:
            results.put(("plan", *out))


class _ThreadLink:
    """The worker as a thread of this process: requests and answers by reference."""

    def __init__(self, driver: PlanDriver, sole_length: float) -> None:
        sys.setswitchinterval(min(sys.getswitchinterval(), SWITCH_INTERVAL))
        self.requests: queue.SimpleQueue[Any] = queue.SimpleQueue()
        self.results: queue.SimpleQueue[Any] = queue.SimpleQueue()
        worker = _Worker(driver, sole_length)
        self.thread = threading.Thread(target=_serve_thread, args=(worker, self.requests, self.results), daemon=True)
        self.thread.start()
        self.close = weakref.finalize(self, self.requests.put, (_QUIT, ()))

    def put(self, tag: bytes, values: tuple[float, ...]) -> None:
        self.requests.put((tag, values))

    def take(self) -> list[tuple[Any, ...]]:
        got = []
        with contextlib.suppress(queue.Empty):
            while True:
                got.append(self.results.get_nowait())
        return got


class _ProcessLink:
    """The worker as a spawned process: fixed-size records on two pipes, read and written without blocking
    on this side; plans and errors in files of a private folder (in /dev/shm when there is one)."""

    def __init__(self, driver: PlanDriver, sole_length: float) -> None:
        self.folder = Path(
            tempfile.mkdtemp(prefix="gaitshift-plans-", dir="/dev/shm" if Path("/dev/shm").is_dir() else None)
        )
        payload = self.folder / "driver.pkl"
        payload.write_bytes(pickle.dumps(driver, protocol=pickle.HIGHEST_PROTOCOL))
        ctx = multiprocessing.get_context("spawn")
        req_r, req_w = ctx.Pipe(duplex=False)
        res_r, res_w = ctx.Pipe(duplex=False)
        args = (req_r, res_w, str(payload), sole_length)
        self.proc = ctx.Process(target=_serve_process, args=args, daemon=True, name="gaitshift-planner")
        self.proc.start()
        req_r.close()
        res_w.close()
        self.out, self.inbox, self.buf = req_w.fileno(), res_r.fileno(), b""
        self.files, self.read = PlanFolder(self.folder), 1  # read: the last take's newest plan (freed before it)
        os.set_blocking(self.out, False)
        os.set_blocking(self.inbox, False)
        self.close = weakref.finalize(self, _stop_process, self.proc, req_w, res_r, str(self.folder))

    def put(self, tag: bytes, values: tuple[float, ...]) -> None:
        try:
            os.write(self.out, _record(tag, values))
        except BlockingIOError as e:
            raise GaitshiftError("the planner worker fell over a thousand requests behind") from e
        except OSError as e:
            raise GaitshiftError(f"the planner worker ended ({e})") from e

    def take(self) -> list[tuple[Any, ...]]:
        try:
            chunk = os.read(self.inbox, _RESULT * 64)
        except BlockingIOError:
            return []
        if not chunk:
            raise GaitshiftError(f"the planner worker ended (exit code {self.proc.exitcode})")
        self.buf += chunk
        whole = len(self.buf) - len(self.buf) % _RESULT
        got = []
        for k in range(0, whole, _RESULT):
            n, replans, tick = struct.unpack("<3q", self.buf[k + 1 : k + _RESULT])
            what = self.files.read(n)
            got.append(("error", what) if self.buf[k : k + 1] == b"E" else ("plan", what, replans, tick))
        self.buf = self.buf[whole:]
        if got:  # the plans before the last take's newest are no longer mapped (the controller holds one)
            self.put(_FREE, (float(self.read),))
            self.read = n
        return got


class _LiveGen:
    """``driver.gen`` as a host sees it: ``goto`` sent to the worker (as :meth:`BackgroundReplan.command`)."""

    def __init__(self, owner: BackgroundReplan) -> None:
        self.owner = owner

    def goto(self, x: float, y: float, yaw: float = 0.0) -> None:
        """Walk to (x, y) m and turn to ``yaw`` rad (from the worker's next planning instant)."""
        if self.owner.mode == "process":
            self.owner.local.gen.goto(x, y, yaw)
        self.owner.send(_GOTO, (float(x), float(y), float(yaw)))


class BackgroundReplan:
    """The driver in a worker thread or process (module docstring). It is also the driver as the host
    sees it (:class:`~gaitshift.control.drivers.PlanDriver`: ``trajectory`` the newest plan taken,
    ``replans`` the worker's re-plans so far, and the live commands of a locomotion driver).

    Args:
        driver: the plan driver, as at the start of the run (the worker gets a copy: a pickle in "process").
        sole_length: m, the robot's sole length. mode: "thread" or "process".

    Attributes:
        lags: per plan taken, the ticks it came late (the tick that took it minus the tick it was due at).
    """

    def __init__(self, driver: PlanDriver, sole_length: float, mode: str) -> None:
        if mode not in REPLAN_MODES[1:]:
            raise InputError("replan", mode, "thread or process for a background re-plan")
        self.local: Any = driver  # the host's copy ("process"): live commands are checked on it
        self.mode = mode
        self.trajectory: Trajectory = driver.trajectory
        self.replans = int(driver.replans)
        self.duration_bound, self.step_feedback = driver.duration_bound, driver.step_feedback
        self.ticks = 0  # tick requests sent
        self.lags: list[int] = []
        self.closed = False
        self.link = _ThreadLink(driver, sole_length) if mode == "thread" else _ProcessLink(driver, sole_length)

    @property
    def driver(self) -> BackgroundReplan:
        """The driver as the host sees it: this object."""
        return self

    def send(self, tag: bytes, values: tuple[float, ...]) -> None:
        """One request to the worker; a closed or dead worker is a :class:`GaitshiftError`."""
        if self.closed:
            raise GaitshiftError("the planner worker is closed")
        self.link.put(tag, values)

    def step(self, t: float, com: np.ndarray, com_vel: np.ndarray) -> list[Update]:
        """Send the tick's ``(t s, com (3,) m, com_vel (3,) m/s)`` and take the plans the worker finished
        (never waits); an error of the worker's driver is raised here."""
        self.send(_TICK, (float(t), *map(float, com[:3]), *map(float, com_vel[:3])))
        self.ticks += 1
        return self.take()

    def take(self) -> list[Update]:
        """The plans the worker finished since the last take, oldest first (never waits); an error of the
        worker's driver is raised here."""
        updates = []
        for msg in self.link.take():
            if msg[0] == "error":
                raise msg[1]
            updates.append(msg[1])
            self.replans = msg[2]
            self.lags.append(self.ticks - msg[3])
        if updates:
            self.trajectory = updates[-1][0]
        return updates

    # --- live commands of a locomotion driver: sent in order with the ticks -------------------------------
    # "process": first applied to the host's copy, so that a bad command raises here; "thread": the worker
    # holds the host's very object, and its error is raised by the next tick

    def command(self, vx: float, vy: float, yaw_rate: float) -> None:
        """A live velocity command (m/s, m/s, rad/s) from the worker's next planning instant."""
        if self.mode == "process":
            self.local.command(vx, vy, yaw_rate)
        self.send(_COMMAND, (float(vx), float(vy), float(yaw_rate)))

    def stop(self) -> None:
        """A live stop request."""
        if self.mode == "process":
            self.local.stop()
        self.send(_STOP, ())

    def __getattr__(self, name: str) -> Any:
        if name == "gen" and "local" in self.__dict__ and hasattr(self.local, "gen"):
            return _LiveGen(self)
        raise AttributeError(name)

    def close(self) -> None:
        """Stop the worker (it finishes the request at hand)."""
        self.closed = True
        self.link.close()


def _stop_process(proc: Any, conn: Connection, inbox: Connection, folder: str) -> None:
    """Ask the worker process to quit, wait for it (1 s), end it otherwise; remove its folder."""
    with contextlib.suppress(OSError):
        os.write(conn.fileno(), _record(_QUIT, ()))
    proc.join(1.0)
    if proc.is_alive():
        proc.terminate()
        proc.join(1.0)
    conn.close()
    inbox.close()
    shutil.rmtree(folder, ignore_errors=True)


def replanner(driver: PlanDriver, mode: str, sole_length: float) -> InlineReplan | BackgroundReplan:
    """Where ``driver`` re-plans: ``mode`` one of :data:`REPLAN_MODES`; ``sole_length`` m."""
    if mode == "inline":
        return InlineReplan(driver, sole_length)
    return BackgroundReplan(driver, sole_length, mode)
