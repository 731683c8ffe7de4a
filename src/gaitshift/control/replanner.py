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
the tick never waits for the worker to write it nor reads the whole plan): the one for real time. The
worker's side is :mod:`gaitshift.control.planner_worker`. A
program that builds a "process" controller must guard its main module (``if __name__ == "__main__":``), as
any program that spawns processes; an error of the worker's driver is raised by the next tick as a
:class:`~gaitshift.errors.GaitshiftError` with its message.

**A driver that reads the map** (``perceives``: the perceived driver): inline, it reads the controller's
own map in the tick. In the background, the tick at or after each of the driver's ``map_instants`` hands
the worker a copy of the map as it is then (:meth:`ElevationMap.snapshot
<gaitshift.control.perception.elevation_map.ElevationMap.snapshot>`; a file of the private folder for a
process), before that tick's request, so the worker re-plans on the map the inline driver would have read.
The driver's ``replan_lead`` gives it that long before the plan is needed.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import pickle
import queue
import shutil
import struct
import sys
import tempfile
import threading
import weakref
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.control.drivers import PlanDriver
from gaitshift.control.plan_files import PlanFolder
from gaitshift.control.plan_samples import PlanSamples
from gaitshift.control.planner_worker import (
    COMMAND,
    FREE,
    GOTO,
    MAP,
    PLANNER_NICE,
    PLANNER_POLL,
    QUIT,
    RESULT_BYTES,
    STOP,
    TICK,
    Update,
    Worker,
    map_folder,
    record,
    serve_process,
    serve_thread,
)
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

    def watch(self, emap: Any) -> None:
        """A perceiving driver reads the controller's own map ``emap`` in the tick."""
        self.driver.see(emap)  # type: ignore[attr-defined]

    def close(self) -> None:
        """Nothing to stop."""


class _ThreadLink:
    """The worker as a thread of this process: requests and answers by reference."""

    def __init__(self, driver: PlanDriver, sole_length: float) -> None:
        sys.setswitchinterval(min(sys.getswitchinterval(), SWITCH_INTERVAL))
        self.requests: queue.SimpleQueue[Any] = queue.SimpleQueue()
        self.results: queue.SimpleQueue[Any] = queue.SimpleQueue()
        worker = Worker(driver, sole_length)
        self.thread = threading.Thread(target=serve_thread, args=(worker, self.requests, self.results), daemon=True)
        self.thread.start()
        self.close = weakref.finalize(self, self.requests.put, (QUIT, ()))

    def put(self, tag: bytes, values: tuple[float, ...]) -> None:
        self.requests.put((tag, values))

    def put_map(self, emap: Any) -> None:
        self.requests.put((MAP, (emap,)))

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
        self.proc = ctx.Process(target=serve_process, args=args, daemon=True, name="gaitshift-planner")
        self.proc.start()
        req_r.close()
        res_w.close()
        self.out, self.inbox, self.buf = req_w.fileno(), res_r.fileno(), b""
        self.files, self.read = PlanFolder(self.folder), 1  # read: the last take's newest plan (freed before it)
        self.maps, self.maps_sent = map_folder(self.folder), 0
        os.set_blocking(self.out, False)
        os.set_blocking(self.inbox, False)
        self.close = weakref.finalize(self, _stop_process, self.proc, req_w, res_r, str(self.folder))

    def put(self, tag: bytes, values: tuple[float, ...]) -> None:
        try:
            os.write(self.out, record(tag, values))
        except BlockingIOError as e:
            raise GaitshiftError("the planner worker fell over a thousand requests behind") from e
        except OSError as e:
            raise GaitshiftError(f"the planner worker ended ({e})") from e

    def put_map(self, emap: Any) -> None:
        self.maps_sent += 1
        self.maps.write(self.maps_sent, emap)
        self.put(MAP, (float(self.maps_sent),))

    def take(self) -> list[tuple[Any, ...]]:
        try:
            chunk = os.read(self.inbox, RESULT_BYTES * 64)
        except BlockingIOError:
            return []
        if not chunk:
            raise GaitshiftError(f"the planner worker ended (exit code {self.proc.exitcode})")
        self.buf += chunk
        whole = len(self.buf) - len(self.buf) % RESULT_BYTES
        got: list[tuple[Any, ...]] = []
        newest = 0
        for k in range(0, whole, RESULT_BYTES):
            tag = self.buf[k : k + 1]
            n, replans, tick = struct.unpack("<3q", self.buf[k + 1 : k + RESULT_BYTES])
            if tag == b"R":
                got.append(("refused", n))
                continue
            what, newest = self.files.read(n), n
            got.append(("error", what) if tag == b"E" else ("plan", what, replans, tick))
        self.buf = self.buf[whole:]
        if newest:  # the plans before the last take's newest are no longer mapped (the controller holds one)
            self.put(FREE, (float(self.read),))
            self.read = newest
        return got


class _LiveGen:
    """``driver.gen`` as a host sees it: ``goto`` sent to the worker (as :meth:`BackgroundReplan.command`)."""

    def __init__(self, owner: BackgroundReplan) -> None:
        self.owner = owner

    def goto(self, x: float, y: float, yaw: float = 0.0) -> None:
        """Walk to (x, y) m and turn to ``yaw`` rad (from the worker's next planning instant)."""
        if self.owner.mode == "process":
            self.owner.local.gen.goto(x, y, yaw)
        self.owner.send(GOTO, (float(x), float(y), float(yaw)))


class BackgroundReplan:
    """The driver in a worker thread or process (module docstring). It is also the driver as the host
    sees it (:class:`~gaitshift.control.drivers.PlanDriver`: ``trajectory`` the newest plan taken,
    ``replans`` the worker's re-plans so far, and the live commands of a locomotion driver).

    Args:
        driver: the plan driver, as at the start of the run (the worker gets a copy: a pickle in "process").
        sole_length: m, the robot's sole length. mode: "thread" or "process".

    Attributes:
        lags: per plan taken, the ticks it came late (the tick that took it minus the tick it was due at).
        refused, stopped: a perceiving driver's re-plans not taken and why its walk stops (its newest plan's
            ``meta["stopped"]``), as the worker reported them; None for other drivers.
        maps_handed: the driver's map instants passed, a copy of the map handed to the worker at the first
            tick at or after each (module docstring, "A driver that reads the map").
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
        self.perceives = bool(getattr(driver, "perceives", False))
        self.refused = getattr(driver, "refused", None) if self.perceives else None
        self.stopped: str | None = None
        self.feed: tuple[Any, np.ndarray] | None = None  # the controller's map and when to hand it over
        self.maps_handed = 0
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

    def watch(self, emap: Any) -> None:
        """Hand the worker a copy of the controller's map ``emap`` at each of the driver's ``map_instants``
        (module docstring, "A driver that reads the map")."""
        self.feed = (emap, np.asarray(self.local.map_instants(), dtype=float))

    def step(self, t: float, com: np.ndarray, com_vel: np.ndarray) -> list[Update]:
        """Send the tick's ``(t s, com (3,) m, com_vel (3,) m/s)`` (after a copy of the map, when one is due)
        and take the plans the worker finished (never waits); an error of the worker's driver is raised here."""
        if self.feed is not None:
            due = int(np.searchsorted(self.feed[1], t + 1e-9, side="right"))
            if due > self.maps_handed:
                if self.closed:
                    raise GaitshiftError("the planner worker is closed")
                self.link.put_map(self.feed[0].snapshot())
                self.maps_handed = due
        self.send(TICK, (float(t), *map(float, com[:3]), *map(float, com_vel[:3])))
        self.ticks += 1
        return self.take()

    def take(self) -> list[Update]:
        """The plans the worker finished since the last take, oldest first (never waits); an error of the
        worker's driver is raised here."""
        updates = []
        for msg in self.link.take():
            if msg[0] == "error":
                raise msg[1]
            if msg[0] == "refused":
                self.refused = msg[1]
                continue
            updates.append(msg[1])
            if self.perceives:
                self.stopped = msg[1][0].meta.get("stopped")
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
        self.send(COMMAND, (float(vx), float(vy), float(yaw_rate)))

    def stop(self) -> None:
        """A live stop request."""
        if self.mode == "process":
            self.local.stop()
        self.send(STOP, ())

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
        os.write(conn.fileno(), record(QUIT, ()))
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
