"""The online VHIP running generator (paper 003): the written file obeys the physics, and the take-off
speed reaches every command at the take-off of the second step after it.

Oracles are recomputed from the file alone: eq. (2) from com_pos/com_acc/zmp, finite differences of
com_pos, ballistic flight, support polygons from the sole rectangles (scipy ConvexHull), take-offs
from the phase sequence. The generator's own records are never used as the reference.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.spatial import ConvexHull

import gaitshift
from gaitshift.errors import InfeasibleError, InputError
from gaitshift.planners.vhip.generator import VhipGenerator, plan_scenario, run_commands
from gaitshift.trajectory.contract import DS, FLIGHT, SS

G = 9.81


@pytest.fixture(scope="module")
def run():
    return gaitshift.plan("paper003-variable-speed")


def _takeoffs(tr) -> np.ndarray:
    """First force-free sample after each single support."""
    ph = tr.phase
    return np.flatnonzero((ph[1:] == FLIGHT) & (ph[:-1] == SS)) + 1


def _stance_side(tr, i: int) -> int:
    return int(np.flatnonzero(tr.contact[i])[0])


def check_physics(tr, tol_zmp=1e-7, accel_jump=0.0) -> None:
    """Every physics check of the file contract for a vhip trajectory (``accel_jump``: largest jump of
    z'' at a contact switch, m/s^2; 0 with the default contact accelerations -g)."""
    g, dt = tr.gravity, tr.dt
    p, v, a = tr.com_pos, tr.com_vel, tr.com_acc
    assert np.all(np.isfinite(p)) and np.all(np.isfinite(v)) and np.all(np.isfinite(a))
    np.testing.assert_allclose(np.diff(tr.t), dt, atol=1e-12)
    stance = tr.phase != FLIGHT
    # eq. (2) at every stance sample, with the file's own acceleration
    pred = p[stance, :2] - (p[stance, 2] / (a[stance, 2] + g))[:, None] * a[stance, :2]
    assert np.max(np.abs(tr.zmp[stance, :2] - pred)) < tol_zmp
    assert np.all(np.isnan(tr.zmp[~stance]))
    # the file's horizontal acceleration is the second difference of the file's positions (eqs. 7-8)
    fd2 = (p[2:, :2] - 2 * p[1:-1, :2] + p[:-2, :2]) / dt**2
    assert np.max(np.abs(fd2 - a[1:-1, :2])) < 1e-6
    fd1 = (p[2:, :2] - p[:-2, :2]) / (2 * dt)
    assert np.max(np.abs(fd1 - v[1:-1, :2])) < 1e-9
    # vertical: analytic polynomials agree with finite differences to O(dt^2) inside a phase and to
    # O(dt) across a contact switch (the jerk jumps there: error = jump * dt / 6)
    fdz = (p[2:, 2] - 2 * p[1:-1, 2] + p[:-2, 2]) / dt**2
    err = np.abs(fdz - a[1:-1, 2])
    switch = np.zeros(len(p), bool)
    switch[np.flatnonzero(np.diff(tr.phase) != 0)[:, None] + np.arange(-1, 3)] = True
    assert np.max(err[~switch[1:-1]]) < 5e3 * dt**2 + 1e-6  # |z''''| dt^2 / 12, sextic
    assert np.max(err) < 300 * dt + accel_jump
    fdvz = (p[2:, 2] - p[:-2, 2]) / (2 * dt)
    assert np.max(np.abs(fdvz - v[1:-1, 2])) < 300 * dt**2 + accel_jump * dt / 2 + 1e-9
    # ballistic flight: a = (0, 0, -g), and the positions follow it
    fl = ~stance
    np.testing.assert_allclose(a[fl], np.broadcast_to([0.0, 0.0, -g], a[fl].shape), atol=1e-12)
    inner = fl[1:-1] & fl[:-2] & fl[2:]
    assert np.max(np.abs(fd2[inner])) < 1e-6 and np.max(np.abs(fdz[inner] + g)) < 1e-6
    # continuity: no position jumps beyond the speed, no velocity jumps beyond the acceleration
    assert np.max(np.abs(np.diff(p, axis=0))) < 3.0 * dt
    assert np.max(np.abs(np.diff(v, axis=0))) < 60.0 * dt
    # the ground only pushes
    assert np.all(a[stance, 2] + g > 0)
    # ZMP inside the support polygon (convex hull of the contacting soles)
    half = np.asarray(tr.meta["foot_size"]) / 2
    corners = np.array([[1, 1], [1, -1], [-1, -1], [-1, 1]]) * half
    for i in np.flatnonzero(stance)[::7]:
        feet = [tr.foot_pos[i, s, :2] for s in (0, 1) if tr.contact[i, s]]
        assert len(feet) == (2 if tr.phase[i] == DS else 1)
        pts = np.vstack([f + corners for f in feet])
        eq = ConvexHull(pts).equations
        assert np.max(tr.zmp[i, :2] @ eq[:, :2].T + eq[:, 2]) <= 1e-9
        assert np.all(np.abs(tr.foot_pos[i, tr.contact[i], 2]) < 1e-12)
    # start and end at rest, ZMP under the CoM
    for i in (0, -1):
        assert np.all(np.abs(v[i]) < 1e-9) and np.all(np.abs(a[i, :2]) < 1e-6)
        np.testing.assert_allclose(tr.zmp[i, :2], p[i, :2], atol=1e-9)
        assert tr.phase[i] == DS


def check_takeoff_speeds(tr, tol=1e-6) -> None:
    """v(to_{j+2}) = command at to_j (x exactly; y plus the periodic oscillation +/- u)."""
    to = _takeoffs(tr)
    assert len(to) >= 2
    cmd = tr.command_vel
    planned_with = np.r_[0, 0, to[:-2]]  # the start plans the first two take-offs at t = 0
    dev_y = []
    for j, i in enumerate(to):
        c = cmd[planned_with[j]]
        assert abs(tr.com_vel[i, 0] - c[0]) <= tol, (j, tr.t[i], tr.com_vel[i, 0], c[0])
        dev_y.append((tr.com_vel[i, 1] - c[1]) * (1 if _stance_side(tr, i - 1) == 0 else -1))
    dev_y = np.array(dev_y)
    # the lateral oscillation: after a left stance the CoM leaves to the right (and vice versa), always
    # with the same magnitude
    assert np.all(dev_y < 0)
    assert np.ptp(dev_y) <= tol


def test_file_passes_the_physics_checks(run):
    check_physics(run)
    assert run.meta["planner"] == "vhip"
    assert np.all(np.isfinite(run.command_vel))


def test_takeoff_speed_reaches_each_command_two_steps_later(run):
    check_takeoff_speeds(run)
    # the scenario's commands are within the limits: nothing was clamped
    assert not [e for e in run.meta["events"] if e["kind"].startswith("clamp")]
    # and the forward commands 0.3, 0.6, 0.9, 0.6, 0.3 all appear as take-off speeds
    seen = {round(float(v), 6) for v in run.com_vel[_takeoffs(run), 0]}
    assert {0.0, 0.3, 0.6, 0.9} <= seen


def test_footholds_are_step_width_apart_in_steady_lateral_oscillation(run):
    to = _takeoffs(run)
    cmd_y = run.command_vel[np.r_[0, 0, to[:-2]], 1]
    feet = np.array([run.foot_pos[i - 1, _stance_side(run, i - 1), :2] for i in to])
    width = run.meta["step_width"]
    checked = 0
    for j in range(1, len(to) - 1):
        if np.all(cmd_y[j - 1 : j + 2] == 0):  # the three take-offs that fix this step are pure oscillation
            assert abs(abs(feet[j + 1, 1] - feet[j, 1]) - width) < 1e-9
            checked += 1
    assert checked >= 5


def test_foothold_iteration_takes_at_most_ten_iterations(run):
    it = run.extras["foothold_iterations"]
    assert len(it) > 20 and it.max() <= 10
    assert it.max() == 1  # docs/vhip.md: the update is exact after one iteration


def _small_scenario(**kw):
    base = {
        "planner": "vhip",
        "dt": 0.004,
        "commands": [{"t": 0.0}],
        "limits": {"max_speed": [1.5, 0.4], "max_stride": 0.9, "max_accel_per_step": [0.3, 0.1]},
    }
    base.update(kw)
    return gaitshift.load_scenario(base)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    st.lists(st.tuples(st.floats(0.4, 1.6), st.integers(-1, 1), st.integers(-1, 1)), min_size=1, max_size=6),
    st.sampled_from(["left", "right"]),
    st.sampled_from([0.0, 0.3]),
    st.sampled_from([0.0, -0.05, 0.1]),
)
def test_random_commands_within_limits_are_reached_two_steps_later(changes, first, vx0, vy0):
    # "within limits": speeds, strides, and at most max_accel_per_step between two planning instants
    # (take-offs, 0.4 s apart; the first one after the start is at 1.48 s): changes >= 0.4 s apart
    sc = _small_scenario(first_support=first)
    t, vx, vy, cmds = 0.7, vx0, vy0, [(0.0, vx0, vy0)]  # the start already runs off at (vx0, vy0)
    for gap, dx, dy in changes:
        t += gap
        vx = float(np.clip(vx + 0.3 * dx, -0.6, 1.2))
        vy = float(np.clip(vy + 0.05 * dy, -0.1, 0.1))
        cmds.append((t, vx, vy))
    while vx != 0.0 or vy != 0.0:  # ramp down within the per-step limits, then stop
        t += 0.8
        vx = float(np.sign(vx) * max(abs(vx) - 0.3, 0.0)) if abs(vx) > 1e-12 else 0.0
        vy = float(np.sign(vy) * max(abs(vy) - 0.05, 0.0)) if abs(vy) > 1e-12 else 0.0
        vx, vy = round(vx, 12), round(vy, 12)
        cmds.append((t, vx, vy))
    gen = run_commands(VhipGenerator(sc), cmds, stop_at=max(t + 0.8, 3.0))
    tr = gen.trajectory()
    assert not [e for e in gen.events if e.kind.startswith("clamp")], gen.events
    check_takeoff_speeds(tr)
    check_physics(tr)


def test_contact_switch_accelerations_are_configurable():
    """touchdown_acc / takeoff_acc above -g: the vertical force jumps at the switch; the touchdown
    sample belongs to the stance, the take-off sample to the flight, and every check still holds."""
    sc = _small_scenario(dt=0.001, heights={"touchdown_acc": -6.0, "takeoff_acc": -9.0})
    tr = run_commands(VhipGenerator(sc), [(0.0, 0.0, 0.0), (1.5, 0.3, 0.0), (3.0, 0.0, 0.0)], stop_at=4.0).trajectory()
    ph = tr.phase
    td = np.flatnonzero((ph[1:] == SS) & (ph[:-1] == FLIGHT)) + 1
    to = _takeoffs(tr)
    np.testing.assert_allclose(tr.com_acc[td, 2], -6.0, atol=1e-9)
    a = tr.com_acc[:, 2]  # stance side of take-off:
    np.testing.assert_allclose(3 * a[to - 1] - 3 * a[to - 2] + a[to - 3], -9.0, atol=0.05)  # extrapolated
    np.testing.assert_allclose(tr.com_acc[to, 2], -G, atol=1e-12)
    check_physics(tr, accel_jump=G - 6.0)
    check_takeoff_speeds(tr)
    with pytest.raises(InfeasibleError, match=r"heights\.takeoff_acc"):
        _small_scenario(heights={"takeoff_acc": -10.5})


def test_commands_beyond_the_limits_are_clamped_and_reported():
    gen = VhipGenerator(_small_scenario())
    # x: limits.max_speed; y: the steady lateral stride step_width - vy T_step must keep one foot width
    np.testing.assert_allclose(gen.command(9.0, -2.0), [1.5, -(0.2 - 0.12) / 0.4], atol=1e-12)
    kinds = [(e.kind, e.field) for e in gen.events]
    assert ("clamp_speed", "command.vx") in kinds and ("clamp_speed", "command.vy") in kinds
    for _ in range(12):
        s = gen.step()
        assert np.all(np.isfinite(s.com_pos)) and np.all(np.isfinite(s.com_vel))
    # the per-step acceleration limit ramps the take-off speed by at most 0.3 m/s per step
    targets = [tk.target[0] for tk in gen.takeoffs]
    assert max(np.diff(targets)) <= 0.3 + 1e-12
    assert any(e.kind == "clamp_accel" for e in gen.events)
    with pytest.raises(InputError, match=r"command\.vx"):
        gen.command(float("nan"), 0.0)
    gen.stop()
    while not gen.finished:
        gen.step()
    check_physics(gen.trajectory())


def test_tick_by_tick_equals_block_advance():
    a, b = VhipGenerator(_small_scenario()), VhipGenerator(_small_scenario())
    a.command(0.3, 0.05)
    b.command(0.3, 0.05)
    for _ in range(900):
        a.tick()
    for _ in range(3):
        b.advance(300)
    ta, tb = a.trajectory(), b.trajectory()
    for key in ("com_pos", "com_vel", "com_acc", "foot_pos", "contact", "phase"):
        np.testing.assert_array_equal(getattr(ta, key), getattr(tb, key))


def test_replan_from_a_measured_state_continues_from_it():
    gen = VhipGenerator(_small_scenario())
    gen.command(0.6, 0.0)
    for _ in range(6):
        gen.step()
    gen.advance(20)
    with pytest.raises(InputError):
        gen.replan([np.nan, 0.0], [0.0, 0.0])
    i = gen.tick_index
    measured = gen.planned_com(i) + np.array([0.02, -0.015])
    vel = np.array([0.65, 0.1])
    target = gen.takeoffs[-1].target.copy()
    gen.replan(measured, vel)
    s = gen.tick()
    np.testing.assert_allclose(s.com_pos[0, :2], measured, atol=1e-12)
    for _ in range(3):
        gen.step()
    gen.stop()
    while not gen.finished:
        gen.step()
    tr = gen.trajectory()
    # the CoM after the re-plan follows the measured velocity (forward Euler of eq. (8))
    np.testing.assert_allclose((tr.com_pos[i + 1, :2] - tr.com_pos[i, :2]) / tr.dt, vel, atol=1e-9)
    # eq. (2), flight, support polygon and rest still hold after the jump; the jump itself is the
    # measured disturbance, so check physics on the samples after it
    to = _takeoffs(tr)
    after = to[to > i]
    # the re-planned step keeps its take-off target exactly
    np.testing.assert_allclose(tr.com_vel[after[1]], np.r_[target, tr.com_vel[after[1], 2]], atol=1e-6)
    stance = (tr.phase != FLIGHT) & (np.arange(len(tr)) > i)
    p, a = tr.com_pos, tr.com_acc
    pred = p[stance, :2] - (p[stance, 2] / (a[stance, 2] + G))[:, None] * a[stance, :2]
    assert np.max(np.abs(tr.zmp[stance, :2] - pred)) < 1e-7
    assert any(e.kind == "replan" for e in gen.events)


def test_without_history_the_generator_keeps_running_but_has_no_trajectory():
    gen = VhipGenerator(_small_scenario(), keep_history=False)
    gen.command(0.3, 0.0)
    blocks = [gen.step() for _ in range(10)]
    assert sum(len(b) for b in blocks) == gen.tick_index
    assert np.all(np.isfinite(blocks[-1].com_pos))
    with pytest.raises(InputError, match="keep_history"):
        gen.trajectory()


def test_replan_outside_running_is_refused():
    gen = VhipGenerator(_small_scenario())
    gen.tick()
    with pytest.raises(InfeasibleError, match="running"):
        gen.replan([0.0, 0.0], [0.0, 0.0])


def test_plan_scenario_writes_the_contract(tmp_path, run):
    for suffix in (".npz", ".json"):
        path = run.save(tmp_path / f"run{suffix}")
        back = gaitshift.Trajectory.load(path)
        assert back.meta["planner"] == "vhip"
        np.testing.assert_array_equal(back.com_pos, run.com_pos)
        assert back.command_vel.shape == (len(back), 2) and np.all(np.isfinite(back.command_vel))
    # plan_scenario is what gaitshift.plan dispatches to for planner: vhip
    again = plan_scenario(gaitshift.load_scenario("paper003-variable-speed"))
    np.testing.assert_array_equal(again.com_pos, run.com_pos)


def test_a_large_disturbance_is_absorbed_by_the_footholds_and_reported():
    """A 1 m/s lateral shove while running: the re-planned foothold absorbs it; the stride limit
    (0.4 m) would need a larger take-off speed change than max_accel_per_step allows, so the target
    moves by exactly that much (reported) and the stride gives; three steps later the footholds are back
    to step_width apart, and the run stops at rest with every physics check holding after the shove."""
    sc = _small_scenario(
        dt=0.001, limits={"max_speed": [1.5, 0.4], "max_stride": 0.4, "max_accel_per_step": [0.3, 0.1]}
    )
    gen = VhipGenerator(sc)
    gen.command(0.3, 0.0)
    for _ in range(6):
        gen.step()
    i = gen.tick_index
    gen.replan(gen.planned_com(i), np.array([0.3, 1.0]))
    clamps = [e for e in gen.events if e.kind == "clamp_stride"]
    assert len(clamps) == 1 and abs(clamps[0].applied - clamps[0].requested) == pytest.approx(0.1)
    for _ in range(6):
        gen.step()
    gen.stop()
    while not gen.finished:
        gen.step()
    tr = gen.trajectory()
    width = np.diff(tr.footsteps[2:-2, 1])
    k = int(np.argmax(np.abs(width)))  # the step that took the shove
    np.testing.assert_allclose(np.abs(width[k + 3 :]), 0.2, atol=1e-9)
    assert np.all(np.isfinite(tr.com_pos)) and np.all(np.abs(tr.com_vel[-1]) < 1e-9)
    after = np.arange(len(tr)) > i
    stance = (tr.phase != FLIGHT) & after
    p, a = tr.com_pos, tr.com_acc
    pred = p[stance, :2] - (p[stance, 2] / (a[stance, 2] + G))[:, None] * a[stance, :2]
    assert np.max(np.abs(tr.zmp[stance, :2] - pred)) < 1e-7
