"""The stride-mean velocity (CoM displacement over two consecutive steps over their duration, in the
heading frame at their middle) equals the applied command: within 1e-3 m/s from the 2nd full stride
after a command within one step's acceleration limit, within 0.03 m/s while turning, and within three
strides after a gait switch completes. Larger jumps ramp at the per-step limit. Computed from the file
arrays (tests/loco_checks.py), independently of the generator."""

from __future__ import annotations

import itertools

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from loco_checks import plan, ss_starts, stride_means


def _windows_after(d, t_cmd, skip):
    """Stride windows starting at or after the ``skip``-th step start that follows ``t_cmd``."""
    s = ss_starts(d)
    after = s[d["t"][s] > t_cmd]
    first = after[skip] if len(after) > skip else None
    return [w for w in stride_means(d) if first is not None and w[0] >= first]


def test_straight_speed_command_is_met_to_1e_3_from_the_second_full_stride():
    cmds = [{"t": 0.0, "vx": 0.3}, {"t": 4.0, "vx": 0.5}, {"t": 8.0, "vx": 0.7}, {"t": 12.0, "vx": 0.45, "vy": 0.05}]
    _, d = plan(cmds, 16.0, gait="walk")
    for c0, c1 in zip(cmds[1:], [*cmds[2:], {"t": 16.0}], strict=True):
        # the 1st full stride after the command spans step starts 1..3, the 2nd starts at the 3rd
        wins = [w for w in _windows_after(d, c0["t"], 2) if d["t"][w[1]] <= c1["t"]]
        assert wins, c0
        for a, _, v in wins:
            assert abs(v[0] - c0["vx"]) < 1e-3, (d["t"][a], v, c0)
            assert abs(v[1] - c0.get("vy", 0.0)) < 1e-3, (d["t"][a], v, c0)


def test_turning_stride_speed_is_within_3_cm_per_s(tour):
    """Strides while turning, once the planned yaw rate (the heading rate in the file) has equalled the
    command for two steps before the stride (the per-step ramp and the deadbeat horizon are over)."""
    _, d = tour
    rate = np.gradient(d["heading"], d["t"])
    s = ss_starts(d)
    checked = 0
    for a, b, v in stride_means(d):
        k = np.searchsorted(s, a)
        if k < 2:
            continue
        lo = s[k - 2]
        cmd_rate = d["command_yaw_rate"][lo:b]
        if abs(cmd_rate[0]) < 0.1 or np.ptp(cmd_rate) > 0 or np.max(np.abs(rate[lo + 1 : b - 1] - cmd_rate[0])) > 1e-6:
            continue
        cmd = d["command_vel"][a]
        assert np.hypot(*(v - cmd)) < 0.03, (d["t"][a], v, cmd)
        checked += 1
    assert checked >= 8


def test_speed_is_met_within_three_strides_after_a_gait_switch():
    """walk 0.5 -> run 1.5 -> walk 0.6: from three strides after each switch completes (the first
    steady step of the new gait), every stride meets the command to 1e-3."""
    _, d = plan([{"t": 0.0, "vx": 0.5}, {"t": 4.0, "vx": 1.5}, {"t": 14.0, "vx": 0.6}], 22.0)
    g, s = d["gait"], ss_starts(d)
    for gait, t0, t1, v_cmd in ((2, 4.0, 14.0, 1.5), (1, 14.0, 22.0, 0.6)):
        mine = [i for i in s if t0 < d["t"][i] < t1 and g[i] == gait]
        # two steps of the new gait in a row: the switch has completed at the second one's start
        done = next(b for a, b in itertools.pairwise(mine) if np.searchsorted(s, b) == np.searchsorted(s, a) + 1)
        start = s[np.searchsorted(s, done) + 6]
        wins = [w for w in stride_means(d) if w[0] >= start and d["t"][w[1]] < t1]
        assert len(wins) >= 3, (gait, len(wins))
        for a, _, v in wins:
            assert abs(v[0] - v_cmd) < 1e-3 and abs(v[1]) < 1e-3, (d["t"][a], v)


def test_a_jump_beyond_the_acceleration_limit_ramps_one_limit_per_step():
    gen, d = plan([{"t": 0.0, "vx": 0.2}, {"t": 4.0, "vx": 0.9}], 10.0, gait="walk")
    step = gen.p.limits.max_accel[0]
    targets = list(_windows_after(d, 4.0, 2))
    # the target climbs 0.2 -> 0.9 by at most `step` per planning instant: at least ceil(0.7/step) instants
    n_ramp = int(np.ceil(0.7 / step))
    reached = list(_windows_after(d, 4.0, n_ramp + 2))
    assert targets and reached
    for a, _, v in reached:
        if d["t"][a] < 9.0:
            assert abs(v[0] - 0.9) < 1e-3
    speeds = [v[0] for _, _, v in stride_means(d)]
    assert np.max(np.diff(speeds)) < 2.5 * step


@settings(max_examples=12, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.floats(0.05, 0.25), st.floats(-0.2, 0.2)), min_size=2, max_size=4), st.floats(0.1, 1.2))
def test_random_command_sequences_at_odd_times_meet_the_speed(changes, v0):
    """Commands at odd times, each within one step's acceleration limit of the last."""
    t, v, cmds = 0.0, v0, [{"t": 0.0, "vx": round(v0, 3)}]
    for dt_cmd, dv in changes:
        t += 3.0 + dt_cmd * 7.3
        v = float(np.clip(v + dv, 0.05, 1.8))
        cmds.append({"t": round(t, 4), "vx": round(v, 3)})
    gen, d = plan(cmds, t + 5.0)
    step = gen.p.limits.max_accel[0]
    for c0, c1 in zip(cmds, [*cmds[1:], {"t": t + 5.0}], strict=True):
        prev = cmds[cmds.index(c0) - 1]["vx"] if cmds.index(c0) else 0.0
        n_ramp = int(np.ceil(abs(c0["vx"] - prev) / step - 1e-9))
        switch_steps = 8  # a gait switch in the window: its transition steps plus three strides
        for a, b, vv in _windows_after(d, c0["t"], 2 + n_ramp + switch_steps):
            if d["t"][b] <= c1["t"] and np.all(d["gait"][a:b] == d["gait"][a]):
                assert abs(vv[0] - c0["vx"]) < 1e-3, (d["t"][a], vv, c0)


def test_a_command_beyond_what_the_stride_limit_holds_runs_at_the_limit_and_stops_at_rest():
    """A held 2.6 m/s (the G1's Froude limit) with the default limits: the applied speed stays at
    max_stride / running step period - one step's acceleration, every step stays within max_stride,
    the stride-mean speed meets that limit, and the stop comes to rest (above the limit the plans
    compromised step after step and no stop reached rest)."""
    gen, d = plan([{"t": 0.0, "vx": 2.6}], 8.0)
    p = gen.p
    cap = p.limits.max_stride / (p.timing.run_single + p.timing.flight) - p.limits.max_accel[0]
    assert abs(p.limits.max_speed[0] - cap) < 1e-12
    strides = np.linalg.norm(np.diff(d["footsteps"][:, :2], axis=0), axis=1)
    assert strides.max() <= p.limits.max_stride + 1e-9
    fast = [v[0] for a, _, v in stride_means(d) if d["t"][a] < 8.0]
    assert abs(max(fast) - cap) < 1e-3
    assert np.abs(d["com_vel"][-1]).max() < 1e-9 and d["t"][-1] < 8.0 + 10.0
