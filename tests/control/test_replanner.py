"""Re-planning off the tick (gaitshift.control.replanner). A background worker (a thread, a spawned
process) fed the same states as the inline driver computes the same plans, bit for bit, and they differ
from the plans of the nominal state (the measured state reached the worker); the plans come at least one
tick after the tick they were due at. While the worker has not finished (stopped with SIGSTOP, or held by
a gate), the controller's ticks return finite commands on the current plan, and the plan is taken by the
first tick after it is done. A worker's error and a dead worker reach the tick as a GaitshiftError; an
unknown mode is an InputError naming ``replan``; the default is inline."""

import math
import os
import signal
import threading
import time
from dataclasses import replace

import numpy as np
import pytest

import gaitshift
from dds_processes import TINY
from gaitshift.control.controller import Controller
from gaitshift.control.replanner import BackgroundReplan, InlineReplan, replanner
from gaitshift.control.settings import ControllerSettings
from gaitshift.control.vhip_driver import VhipDriver
from gaitshift.dds.warmup import still_frame
from gaitshift.errors import GaitshiftError, InputError
from replan_checks import assert_same, wait_for

#: m, the measured CoM's offset from the plan: the re-plans move the footholds
DISPLACED = np.array([0.0, 0.03, 0.0])


def feed(rp, plan, samples):
    """Each sample's plan time with the displaced planned CoM; the updates returned on the way."""
    out = []
    for k in range(samples):
        out += rp.step(float(plan.t[k]), plan.com_pos[k] + DISPLACED, plan.com_vel[k])
    return out


@pytest.mark.parametrize("mode", ["thread", "process"])
def test_a_background_replan_is_the_inline_one_for_the_same_state(mode):
    sc = gaitshift.load_scenario("g1-online-variable-speed")
    inline = InlineReplan(VhipDriver(sc), 0.2)
    plan = inline.driver.trajectory
    samples = round(2.8 / plan.dt)  # the VHIP run's first planning instants
    expected = feed(inline, plan, samples)
    assert len(expected) >= 2 and inline.driver.replans == len(expected)
    bg = replanner(VhipDriver(sc), mode, 0.2)
    try:
        got = feed(bg, plan, samples)
        got += wait_for(bg, len(expected) - len(got))
    finally:
        bg.close()
    assert len(got) == len(expected) and bg.replans == len(expected) and bg.trajectory is got[-1][0]
    for (traj, ps), (traj_e, ps_e) in zip(got, expected, strict=True):
        assert traj is not traj_e
        assert_same(traj, traj_e)
        assert_same(ps, ps_e)
    # the displaced state was used: the footholds after the first re-plan moved sideways
    moved = np.abs(got[-1][0].footsteps[:, 1] - plan.footsteps[: len(got[-1][0].footsteps), 1])
    assert moved.max() > 1e-3
    assert min(bg.lags) >= 1


def tiny_controller(tmp_path, replan, driver_wrap=None):
    (tmp_path / "tiny.yaml").write_text(TINY)
    ctrl = Controller.from_scenario(tmp_path / "tiny.yaml", contact="torque", replan="inline")
    if replan == "inline":
        return ctrl
    driver = ctrl.driver if driver_wrap is None else driver_wrap(ctrl.driver)
    return Controller(ctrl.traj, ctrl.robot, ControllerSettings.of(contact="torque", replan=replan), driver)


class Gated:
    """A driver whose re-plans wait for a gate (thread mode: the object is used as is)."""

    def __init__(self, driver):
        self.inner, self.gate, self.calls = driver, threading.Event(), 0

    def __getattr__(self, name):
        return getattr(self.inner, name)

    def maybe_replan(self, t, com, com_vel):
        self.calls += 1
        self.gate.wait()
        return self.inner.maybe_replan(t, com, com_vel)


def hold(ctrl, mode):
    """Stop the worker; the function that lets it go on."""
    if mode == "process":
        pid = ctrl.replan.link.proc.pid
        os.kill(pid, signal.SIGSTOP)
        return lambda: os.kill(pid, signal.SIGCONT)
    return ctrl.driver.local.gate.set


@pytest.mark.parametrize("mode", ["thread", "process"])
def test_ticks_during_a_pending_replan_return_commands_and_the_plan_comes_later(tmp_path, mode):
    ctrl = tiny_controller(tmp_path, mode, Gated if mode == "thread" else None)
    assert isinstance(ctrl.replan, BackgroundReplan) and ctrl.driver is ctrl.replan
    start_plan = ctrl.trajectory
    release = hold(ctrl, mode)
    frame = still_frame(ctrl, 0.0)
    held = 40
    try:
        for k in range(held):  # the look-ahead refresh is due at tick 0 (a new step): pending
            cmd = ctrl.tick(replace(frame, t=k * ctrl.period))
            assert np.isfinite(cmd.tau).all() and cmd.tau.shape == (ctrl.robot.model.nu,)
            assert ctrl.trajectory is start_plan
    finally:
        release()
    k, end = held, time.monotonic() + 120.0
    while ctrl.trajectory is start_plan and time.monotonic() < end:
        time.sleep(0.005)
        ctrl.tick(replace(frame, t=k * ctrl.period))
        k += 1
    ctrl.replan.close()
    assert ctrl.trajectory is not start_plan
    assert ctrl.replan.lags[0] >= held
    assert ctrl.sched.traj is ctrl.trajectory and ctrl.traj is ctrl.trajectory


def test_a_worker_error_is_raised_by_the_tick_and_a_dead_worker_is_a_gaitshift_error(tmp_path):
    class Failing(Gated):
        def maybe_replan(self, t, com, com_vel):
            raise InputError("command", t, "a test failure")

    ctrl = tiny_controller(tmp_path, "thread", Failing)
    frame = still_frame(ctrl, 0.0)
    with pytest.raises(GaitshiftError, match="a test failure"):
        for _ in range(2000):
            ctrl.tick(frame)
            time.sleep(0.005)
    ctrl = tiny_controller(tmp_path, "process")
    ctrl.replan.link.proc.kill()
    ctrl.replan.link.proc.join()
    with pytest.raises(GaitshiftError, match="the planner worker ended"):
        ctrl.tick(frame)
        ctrl.tick(frame)


def test_the_default_is_inline_and_an_unknown_mode_is_an_input_error(tmp_path):
    ctrl = tiny_controller(tmp_path, "inline")
    assert ctrl.settings.replan == "inline" and isinstance(ctrl.replan, InlineReplan)
    assert ctrl.driver is ctrl.replan.driver and not math.isnan(ctrl.duration_bound)
    with pytest.raises(InputError, match=r"^replan = 'later' is invalid"):
        ControllerSettings(replan="later")


@pytest.mark.parametrize("mode", ["thread", "process"])
def test_a_live_command_reaches_the_worker_in_tick_order(tmp_path, mode):
    """The same ticks and the same command between ticks 50 and 51: the background plans are the inline ones
    (the command applied once); in a process a bad command raises at once (checked on the host's copy)."""
    from gaitshift.control.locomotion_driver import LocomotionDriver

    (tmp_path / "tiny.yaml").write_text(TINY)
    ctrl = Controller.from_scenario(tmp_path / "tiny.yaml", contact="torque")
    make = lambda: LocomotionDriver(ctrl.driver.sc, None, ctrl.period)  # noqa: E731
    inline, bg = InlineReplan(make(), 0.2), replanner(make(), mode, 0.2)
    plan, expected, got = inline.driver.trajectory, [], []
    try:
        for k in range(300):
            if k == 51:
                inline.driver.command(0.4, 0.0, 0.1)
                bg.command(0.4, 0.0, 0.1)
            t = k * ctrl.period
            expected += inline.step(t, plan.com_pos[k], plan.com_vel[k])
            got += bg.step(t, plan.com_pos[k], plan.com_vel[k])
        got += wait_for(bg, len(expected) - len(got))
    finally:
        bg.close()
    assert len(got) == len(expected) >= 2
    for (traj, ps), (traj_e, ps_e) in zip(got, expected, strict=True):
        assert_same(traj, traj_e)
        assert_same(ps, ps_e)
    # the command changed the plan: the last one's commanded speed reaches 0.4 m/s
    assert np.isclose(got[-1][0].command_vel[:, 0].max(), 0.4)
    if mode == "process":
        with pytest.raises(InputError):
            bg.command(float("nan"), 0.0, 0.0)
