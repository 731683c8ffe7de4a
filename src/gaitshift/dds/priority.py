"""A real-time priority for the thread that ticks (Linux ``SCHED_FIFO``), as a robot's control loop runs.

On a shared machine the kernel's fair scheduler lets any other runnable thread take the core in the middle
of a tick; a tick of 1.2 ms (p50) then ends past its 2 ms. ``SCHED_FIFO`` at ``priority`` (1-99) runs the
thread whenever it is ready, before every normal thread, until it waits again. Only the calling thread is
moved (on Linux ``sched_setscheduler(0)`` is per thread): DDS's receive threads stay normal, on whichever core
is free. The kernel's real-time throttling (95 % of each second by default) keeps a loop that never waits
from freezing the machine; ours waits for every state. Setting it needs the right to (root, or
``CAP_SYS_NICE``, or ``ulimit -r`` at least ``priority``): without it, one line and exit 2.
"""

import os

from gaitshift.errors import InputError

__all__ = ["PRIORITY_RANGE", "check_priority", "set_priority"]

#: SCHED_FIFO priorities Linux allows
PRIORITY_RANGE = (1, 99)


def check_priority(priority: int | None, flag: str) -> None:
    """``priority`` None or an integer in :data:`PRIORITY_RANGE`; :class:`InputError` naming ``flag``."""
    lo, hi = PRIORITY_RANGE
    if priority is None:
        return
    if isinstance(priority, bool) or not isinstance(priority, int) or not lo <= priority <= hi:
        raise InputError(flag, priority, f"an integer in [{lo}, {hi}] (SCHED_FIFO), or none")


def set_priority(priority: int | None, flag: str) -> None:
    """Run the calling thread under ``SCHED_FIFO`` at ``priority`` (None: leave it); :class:`InputError`
    naming ``flag`` when the system refuses."""
    check_priority(priority, flag)
    if priority is None:
        return
    try:
        os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(priority))
    except (PermissionError, OSError) as e:
        allowed = "a priority this user may set: SCHED_FIFO needs root, CAP_SYS_NICE or ulimit -r"
        raise InputError(flag, priority, f"{allowed} ({e.strerror})") from None
