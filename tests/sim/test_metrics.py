"""Summary metrics of a run, on synthetic runs whose answers are known by construction.

A "run" here is the plan itself replayed as measurements (perfect tracking, measured contacts = planned
contacts), then altered in one known way (a constant speed offset, half of every flight lost, a tilt,
a torque peak, an early end); each metric must report exactly that alteration.
"""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np
import pytest

import gaitshift
from gaitshift.control.vhip_driver import VhipDriver
from gaitshift.sim.metrics import format_metrics, step_labels, summarize
from gaitshift.sim.result import SimResult

LIMIT = np.full(29, 100.0)


def replay(traj, n=None):
    """A SimResult that is the plan exactly, one tick per plan sample (first ``n`` samples)."""
    n = len(traj) if n is None else n
    qpos = np.zeros((n, 36))
    qpos[:, 3] = 1.0
    arrays = {
        "t": traj.t[:n].copy(),
        "plan_index": np.arange(n),
        "com_pos": traj.com_pos[:n].copy(),
        "com_ref": traj.com_pos[:n].copy(),
        "com_shift": np.zeros((n, 3)),
        "com_vel": traj.com_vel[:n].copy(),
        "contact": traj.contact[:n].copy(),
        "qpos": qpos,
        "tau": np.zeros((n, 29)),
        "qp_ok": np.ones(n, bool),
    }
    return SimResult(arrays, False, math.nan, "", {"real_time_factor": 1.0}, {})


@pytest.fixture(scope="module")
def run_plan():
    return gaitshift.plan("g1-walk-run-walk")


def test_step_labels_are_stand_outside_the_steps_and_the_step_gaits_inside(run_plan):
    traj = run_plan
    labels = step_labels(traj)
    c = traj.contact
    first_lift = np.flatnonzero(np.any(c[:-1] & ~c[1:], axis=1))[0] + 1
    last_land = np.flatnonzero(np.any(~c[:-1] & c[1:], axis=1))[-1] + 1
    assert set(labels[:first_lift]) == {"stand"} and set(labels[last_land:]) == {"stand"}
    inside = labels[first_lift:last_land]
    assert set(inside) == {"walk", "run"}
    changes = [inside[0]] + [b for a, b in itertools.pairwise(inside) if a != b]
    assert changes == ["walk", "run", "walk"]
    assert set(step_labels(gaitshift.plan("g1-walk"))) == {"stand", "walk"}


def test_perfect_replay_has_zero_error_all_steps_and_all_flight(run_plan):
    traj = run_plan
    met = summarize(replay(traj), traj, LIMIT)
    assert not met["fell"]
    for rms in (*met["com_rms"].values(), *met["com_rms_plan"].values()):
        assert rms == [0.0, 0.0, 0.0]
    rising = np.sum(~traj.contact[:-1] & traj.contact[1:])  # touchdowns of each foot
    assert met["steps_planned"] == met["steps_completed"] == rising
    assert met["flight_ratio"] == pytest.approx(1.0, abs=1e-9)
    assert met["peak_torque_fraction"] == 0.0 and met["max_pelvis_tilt_deg"] == 0.0
    assert met["qp_failures"] == 0


def test_losing_half_of_every_flight_halves_the_flight_ratio(run_plan):
    traj = run_plan
    result = replay(traj)
    air = ~np.any(traj.contact, axis=1)
    edges = np.flatnonzero(np.diff(np.r_[0, air.astype(int), 0]))
    for a, b in zip(edges[::2], edges[1::2], strict=True):
        result.arrays["contact"][a + (b - a) // 2 : b] = True  # touching during the second half
    met = summarize(result, traj, LIMIT)
    assert met["flight_ratio"] == pytest.approx(0.5, abs=0.02)


def test_tilt_torque_and_qp_failures_are_reported_as_made(run_plan):
    traj = run_plan
    result = replay(traj)
    a = result.arrays
    a["qpos"][100, 3:7] = (math.cos(math.radians(5)), math.sin(math.radians(5)), 0.0, 0.0)  # 10 deg roll
    a["tau"][200, 7] = -73.0
    a["qp_ok"][300:305] = False
    met = summarize(result, traj, LIMIT)
    assert met["max_pelvis_tilt_deg"] == pytest.approx(10.0, abs=1e-9)
    assert met["peak_torque_fraction"] == pytest.approx(0.73)
    assert met["qp_failures"] == 5
    assert met["legs_touch_time"] == 0.0 and met["feet_overlap_time"] == 0.0  # a log without the keys


def test_leg_clearance_times_are_the_logged_ticks_times_the_period(run_plan):
    traj = run_plan
    result = replay(traj)
    a = result.arrays
    n, dt = len(a["t"]), float(traj.t[1] - traj.t[0])
    a["legs_touch"], a["feet_overlap"] = np.zeros(n, bool), np.zeros(n, bool)
    a["legs_touch"][50:57] = True
    a["feet_overlap"][[10, 400]] = True
    a["t"][:20] = 0.0  # plan time stalls while the robot settles: the period comes from the meta
    result.meta["control_period"] = dt
    met = summarize(result, traj, LIMIT)
    assert met["legs_touch_time"] == pytest.approx(7 * dt) and met["feet_overlap_time"] == pytest.approx(2 * dt)
    assert "legs touch / feet overlap (s)" in format_metrics(met)


def test_a_run_that_ends_early_completes_only_the_touchdowns_before_its_end(run_plan):
    traj = run_plan
    n = len(traj) // 2
    met = summarize(replay(traj, n), traj, LIMIT)
    c = traj.contact
    land_t = traj.t[np.flatnonzero(np.any(~c[:-1] & c[1:], axis=1)) + 1]
    assert met["steps_completed"] == np.sum(land_t <= traj.t[n - 1]) < met["steps_planned"]


def test_speed_error_is_the_measured_minus_commanded_speed_two_steps_after_each_command():
    traj = VhipDriver(gaitshift.load_scenario("g1-online-variable-speed")).trajectory
    result = replay(traj)
    result.arrays["com_vel"][:, 0] += 0.05
    met = summarize(result, traj, LIMIT)
    errs = met["speed_errors"]
    assert len(errs) >= 6
    commands = {float(v) for v in traj.command_vel[:, 0] if np.isfinite(v)}
    for _, cmd, meas, err, plan in errs:
        assert cmd in commands
        assert meas - plan == pytest.approx(0.05, abs=1e-9)
        assert err == pytest.approx(meas - cmd, abs=1e-12)
    assert met["speed_error_max"] == pytest.approx(max(abs(e[3]) for e in errs))


def test_table_lists_the_metrics_of_the_run(run_plan):
    met = summarize(replay(run_plan), run_plan, LIMIT)
    table = format_metrics(met)
    for row in ("fell", "steps completed", "CoM RMS walk", "CoM RMS run", "flight planned", "peak torque"):
        assert row in table
    assert math.isnan(met["speed_error_max"])  # no command in a TV-LIPM plan: NaN here, null in files
    assert "controller's state" not in table  # a replay without the sensing metrics
    est = {"contact_accuracy": 0.971, "base_vel_rmse": 0.0086, "tilt_rmse": 0.0013}
    named = format_metrics(met | {"state_source": "estimated", "estimation": est})
    assert any(line.startswith("controller's state") and line.endswith(" estimated") for line in named.splitlines())
    assert "97.1 % / 0.0086 m/s / 0.0013 rad RMS" in named


def test_a_fall_before_the_first_tick_gives_complete_finite_metrics_and_a_table():
    import json

    from gaitshift.api import plan
    from gaitshift.common.jsonsafe import finite_json
    from gaitshift.sim.log import TickLog
    from gaitshift.sim.metrics import format_metrics, summarize
    from gaitshift.sim.plant import build_plant
    from gaitshift.sim.result import SimResult

    plant = build_plant()
    traj = plan("g1-walk")
    arrays = TickLog(10, plant.model).arrays(0)
    result = SimResult(arrays, True, 0.0, "pelvis below 60% of its initial height", {"real_time_factor": 0.0}, {})
    metrics = summarize(result, traj, plant.torque_limit)
    assert metrics["fell"] is True and metrics["fall_time"] == 0.0 and metrics["steps_completed"] == 0
    assert metrics["peak_torque_fraction"] == 0.0
    json.loads(json.dumps(finite_json(metrics), allow_nan=False))
    table = format_metrics(metrics)
    assert "0.000  (pelvis below 60% of its initial height)" in table


def test_a_circle_at_constant_speed_reads_that_speed(run_plan):
    """Physics identity: a CoM on a circle of radius R at speed v, the plan's heading along the tangent,
    travels v per second forward whatever its world direction (world x alone read 0.53 of 1.5 m/s on a
    turning run)."""
    traj = run_plan
    v, radius = 1.5, 20.0  # heading from pi/2 (along world y) turning left by about 1 rad: world x reads <= 0
    psi = math.pi / 2 + v / radius * (traj.t - traj.t[0])
    com = np.column_stack([radius * np.sin(psi), -radius * np.cos(psi), traj.com_pos[:, 2]])
    turning = dataclasses.replace(traj, heading=(psi + math.pi) % (2.0 * math.pi) - math.pi)
    result = replay(turning)
    result.arrays["com_pos"] = com
    met = summarize(result, turning, LIMIT)
    assert met["mean_forward_speed_max"] == pytest.approx(v, rel=1e-4)
