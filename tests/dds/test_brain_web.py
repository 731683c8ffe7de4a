"""The brain's browser page (``gaitshift dds control --web``, :mod:`gaitshift.dds.brain_web`).

In one process, no DDS: the page's vx slider, set by Debian's Chromium (headless, playwright), and its
*End run* button reach the brain's command input (:class:`~gaitshift.dds.cmdvel.CommandInput`, fed by the
page's :class:`~gaitshift.dds.cmdvel.CommandQueue`) as the slider's speed and then the stop, which it hands
to the controller; the page shows the brain's phase and, once it is given a tick's record, its thread
poses the brain's own model at the record's estimate and the panel shows the phase and the plan's command.

Between real processes on the loopback (a fresh pid-derived DDS domain, lockstep): ``gaitshift dds robot
g1`` and ``gaitshift dds control live.yaml --web`` on a live scenario that stands until told otherwise.
Chromium moves the page's vx slider: the page then shows the brain's plan carrying that speed, the
robot (whose truth the brain never sees) walks forward without falling, and *End run* ends the plan:
the brain exits 0 with the page's commands applied and none dropped."""

import json
import os
import re
import signal
import socket
import time
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from browser_pages import headless_chromium, open_page
from dds_processes import BRAIN_FLAGS, FakeController, finish, gaitshift, live_scenario

#: offset 42 on test_robot_process.py's pid-derived base (see test_cmdvel.py): within DDS's 232
DOMAIN = 100 + os.getpid() % 90 + 42
LIVE = live_scenario("web-steered")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def wait_for(path: Path, pattern: str, proc, timeout: float) -> re.Match[str]:
    """The first match of ``pattern`` in the file ``path`` that ``proc`` writes (fails if it exits first)."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        m = re.search(pattern, path.read_text())
        if m:
            return m
        assert proc.poll() is None, f"exited {proc.returncode}: {path.read_text()[-2000:]}"
        time.sleep(0.1)
    raise AssertionError(f"no {pattern!r} in {path}: {path.read_text()[-2000:]}")


def set_vx(page, vx: float) -> float:
    """Type ``vx`` m/s in the number box of the page's vx slider (the first; one command, where the slider's
    arrow key sends one per step); the value the slider took, m/s."""
    box = page.get_by_role("textbox").first
    box.fill(f"{vx:g}")
    box.press("Enter")
    slider = page.get_by_role("slider").first
    page.wait_for_function(
        "s => Number(s.getAttribute('aria-valuenow')) > 0.1", arg=slider.element_handle(), timeout=60_000
    )
    return float(slider.get_attribute("aria-valuenow"))


@pytest.fixture
def browser():
    with headless_chromium() as b:
        yield b


def test_the_pages_slider_and_end_run_reach_the_brains_command_input(browser, tmp_path):
    """No DDS: the slider's vx, then the stop, through the page's queue into CommandInput and the controller."""
    from gaitshift.cli.dds_live import live_inputs
    from gaitshift.control.controller import Controller
    from gaitshift.dds.cmdvel import CommandInput, live_limits

    (tmp_path / "live.yaml").write_text(LIVE)
    ctrl = Controller.from_scenario(str(tmp_path / "live.yaml"), replan="inline")
    lines: list[str] = []
    with live_inputs(ctrl, False, (True, free_port()), False, lines.append) as (queues, feed):
        assert [q.name for q in queues] == ["the web page"] and feed is not None
        inp = CommandInput(queues, live_limits(ctrl), lines.append)
        page = open_page(browser, feed.view.url)
        feed.offer("hold", None, ctrl.trajectory)
        page.get_by_text("waiting for the controller's first tick").wait_for(timeout=30_000)
        vx = set_vx(page, 0.3)
        deadline = time.monotonic() + 30
        while inp.pending is None and time.monotonic() < deadline:
            time.sleep(0.05)
            inp.poll()
        assert inp.pending is not None and inp.pending.vx == pytest.approx(vx) and inp.pending.stop == 0
        page.get_by_role("button", name="End run").click(timeout=30_000)
        while not inp.pending.stop and time.monotonic() < deadline + 30:
            time.sleep(0.05)
            inp.poll()
        # a tick's record: the estimate at the start pose, the plan's first sample, drawn by the feed's thread
        est = SimpleNamespace(qpos=ctrl.initial_qpos(), qvel=np.zeros(ctrl.robot.model.nv))
        record = SimpleNamespace(t=0.0, estimate=est)
        feed.offer("locomotion", record, ctrl.trajectory)
        while feed.shown is not record and time.monotonic() < deadline + 60:
            time.sleep(0.05)
        status = feed.view.status.content
    fake = FakeController()
    inp.apply(fake)
    assert fake.calls == [("stop",)] and inp.dropped == 0  # the stop is kept over the speed
    assert inp.accepted >= 2 and any(line.startswith("live commands from the web page: vx [") for line in lines)
    assert feed.shown is record and np.array_equal(feed.data.qpos, est.qpos)  # the estimate, posed
    assert status.startswith("brain: **locomotion**") and "commanded: vx = +0.00" in status  # the plan's own


def test_the_browser_page_steers_the_brain_between_real_processes(browser, tmp_path):
    """Chromium's vx reaches the brain's plan, the robot walks, End run ends the run: exit 0."""
    (tmp_path / "live.yaml").write_text(LIVE)
    port = free_port()
    flags = [*BRAIN_FLAGS, "--no-warm-up", "--web", "--web-port", str(port), "--json", "--state-timeout", "60"]
    flags[flags.index("--stale-limit") + 1] = "1.0"  # the browser shares the 2 loaded cores
    brain, bfiles = gaitshift(
        tmp_path, "brain", "dds", "control", str(tmp_path / "live.yaml"), "--domain", str(DOMAIN), *flags
    )
    robot, rfiles = None, ()
    try:
        url = wait_for(tmp_path / "brain.err", r"web view: (http://\S+)", brain, 60).group(1)
        page = open_page(browser, url)  # it loads while the brain waits for the robot: not during its ticks
        page.get_by_text("End run").wait_for(timeout=60_000)
        argv = ["dds", "robot", "g1", "--domain", str(DOMAIN), "--lockstep", "--summary", str(tmp_path / "robot.json")]
        robot, rfiles = gaitshift(tmp_path, "robot", *argv)
        page.get_by_text("commanded: vx = +0.00").wait_for(timeout=90_000)  # the controller ticks
        vx = set_vx(page, 0.3)
        page.get_by_text(f"commanded: vx = {vx:+.2f} m/s").wait_for(timeout=60_000)  # the brain's plan carries it
        t0 = float(re.search(r"t = (\d+\.\d+) s", page.inner_text("body")).group(1))
        page.wait_for_function(
            f"() => Number((document.body.innerText.match(/t = (\\d+\\.\\d+) s/) || [0, 0])[1]) > {t0 + 1.0}",
            timeout=90_000,
        )
        page.get_by_role("button", name="End run").click(timeout=60_000)
        finish(brain, bfiles)  # the stop, then the damping: 17 ms a lockstep tick on two loaded cores
    finally:
        if robot is not None:
            robot.send_signal(signal.SIGTERM)
            finish(robot, rfiles)
        if brain.poll() is None:
            finish(brain, bfiles, timeout=0.1)
    err = (tmp_path / "brain.err").read_text()
    assert brain.returncode == 0, err[-2000:]
    s = json.loads((tmp_path / "brain.out").read_text())
    r = json.loads((tmp_path / "robot.json").read_text())
    assert s["phase"] == "stop" and s["reason"] == "the plan ended"
    assert s["commands_applied"] >= 2 and s["commands_dropped"] == 0  # the speed, then the stop
    assert "live commands from the web page: vx [" in err
    assert not r["fell"] and r["distance"] > 0.1  # it walked on the page's command (standing otherwise)
