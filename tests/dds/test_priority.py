"""The tick's real-time priority (gaitshift.dds.priority): SCHED_FIFO on the calling thread only (the others,
DDS's receive threads among them, stay normal), or one InputError naming the flag when the system refuses;
bad values are refused before anything runs."""

import os
import threading

import pytest

from gaitshift.dds.priority import set_priority
from gaitshift.errors import InputError


def test_the_calling_thread_alone_runs_under_sched_fifo_or_the_refusal_names_the_flag():
    seen: dict[str, object] = {}

    def tick_thread():
        try:
            set_priority(10, "--rt-priority")
            seen["policy"] = os.sched_getscheduler(0)
        except InputError as e:
            seen["error"] = e

    worker = threading.Thread(target=tick_thread)
    worker.start()
    worker.join()
    assert os.sched_getscheduler(0) == os.SCHED_OTHER  # this thread untouched
    if "error" in seen:  # a user without the right: one line naming the flag
        assert str(seen["error"]).startswith("--rt-priority")
    else:
        assert seen["policy"] == os.SCHED_FIFO


@pytest.mark.parametrize("bad", [0, 100, True, 2.5, "high"])
def test_a_priority_outside_1_to_99_is_refused_before_anything_runs(bad):
    with pytest.raises(InputError, match="--rt-priority"):
        set_priority(bad, "--rt-priority")
