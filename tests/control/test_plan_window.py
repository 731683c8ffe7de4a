"""A live plan of constant size (gaitshift.control.locomotion_driver, gaitshift.control.plan_history): the
driver hands the loop a window of the run that does not grow with it, and the windows, each taken from the
tick that adopted it, put together give the plan the generator emitted, sample for sample."""

import numpy as np

import gaitshift
from gaitshift.control.drivers import prepare
from gaitshift.control.locomotion_driver import LOOKAHEAD_STEPS, WINDOW_BACK
from gaitshift.control.plan_history import PlanHistory
from gaitshift.trajectory.contract import OPEN_END
from gaitshift.trajectory.window import first_index, index_at, window

DT = 0.002


def test_a_long_live_run_is_tracked_on_windows_of_constant_size_that_join_to_the_emitted_plan():
    sc = {"planner": "locomotion", "robot": "g1", "commands": [{"t": 0.0, "vx": 0.6}], "stop_at": 24.0}
    _, _, driver, plan = prepare(sc, None, DT)
    history, sizes = PlanHistory(plan), [len(plan)]
    k = 0
    while not driver.gen.finished:
        t = k * DT
        j = index_at(driver.trajectory, t)
        new = driver.maybe_replan(t, driver.trajectory.com_pos[j], driver.trajectory.com_vel[j])
        if new is not None:
            assert first_index(new) <= k  # the tick that adopts it is inside it
            history.adopt(new, k)
            sizes.append(len(new))
        k += 1
    whole = history.whole()
    emitted = driver.gen.emitted()
    assert len(emitted) > 12_000  # the run: 24 s of walking and the stop
    # each window: a second back and the look-ahead (a few steps of the G1, < 0.5 s each)
    assert max(sizes) <= round(WINDOW_BACK / DT) + LOOKAHEAD_STEPS * round(1.0 / DT)
    for key in ("t", "com_pos", "com_vel", "zmp", "phase", "contact", "foot_pos", "heading"):
        np.testing.assert_array_equal(getattr(whole, key)[: len(emitted)], getattr(emitted, key), err_msg=key)
    np.testing.assert_array_equal(whole.footsteps, driver.trajectory.footsteps)


def test_a_plan_adopted_after_the_last_one_ended_takes_over_where_it_stopped():
    """A background re-plan that comes late: the loop held the last plan's last sample; the history takes the
    new plan from the old one's end, so the run's plan has no gap (and two plans at one tick, none lost)."""
    sc = gaitshift.load_scenario({"gait": [{"gait": "walk", "steps": 3}], "dt": 0.01})
    traj = gaitshift.plan(sc)
    history = PlanHistory(window(traj, 0, 100))
    history.adopt(window(traj, 40, 200), 130)  # came 30 samples after the first plan's end
    history.adopt(window(traj, 150), 180)
    history.adopt(window(traj, 160), 180)  # two at one tick
    whole = history.whole()
    for key in ("t", "com_pos", "contact", "foot_pos"):
        np.testing.assert_array_equal(getattr(whole, key), getattr(traj, key), err_msg=key)
    np.testing.assert_array_equal(whole.extras["boundary_t"], traj.extras["boundary_t"])


def test_a_stop_asked_for_before_any_step_closes_the_live_plan():
    """A live session told to stop while it still stands (``teleop --script quit``) ends: the driver's
    plan, open-ended while the generator stands waiting for commands, closes half a second after the
    generator came to rest, so the controller's run has an end. (Before, the plan stayed open and the
    session stood forever.)"""
    sc = {"planner": "locomotion", "robot": "g1", "commands": [{"t": 0.0, "vx": 0.0}], "stop_at": 60.0}
    _, _, driver, _ = prepare(sc, None, DT)
    for k in range(round(1.0 / DT)):
        if k == 10:  # standing, its plan open-ended
            assert driver.trajectory.meta[OPEN_END] and not driver.gen.finished
            driver.stop()
        t = k * DT
        j = index_at(driver.trajectory, t)
        driver.maybe_replan(t, driver.trajectory.com_pos[j], driver.trajectory.com_vel[j])
    assert driver.gen.finished and not driver.trajectory.meta[OPEN_END]
    assert float(driver.trajectory.t[-1]) <= 0.6  # it ends: rest, then half a second of standing
    assert np.ptp(driver.trajectory.com_pos, axis=0).max() < 1e-9  # standing still, no step taken
