"""3D-SLIP baseline and the Fig. 9 comparison of paper 001 §IV-C.

Oracles are physical identities recomputed here independently of gaitshift.models.slip: the flight is
a closed-form parabola, the stance is re-integrated with our own spring law and a different integrator
(Radau), the energy is recomputed from its definition, and the TV-LIPM samples are checked against
eq. (1) by finite differences.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from gaitshift.analysis.slip_compare import compare, tvlip_half_cycle
from gaitshift.errors import InfeasibleError, InputError
from gaitshift.models import slip

P = slip.SlipParams()


@pytest.fixture(scope="module")
def gait() -> slip.PeriodicGait:
    return slip.periodic_half_cycle(3.5, flight=0.2, step_width=0.1)


@pytest.fixture(scope="module")
def cmp():
    return compare(3.5, slip_repeats=1, tvlip_repeats=3)


def _independent_half_cycle(state0, theta, phi, params=P):
    """TOF -> TOF with analytic flights and a Radau stance on our own spring law."""
    g, k, m, l0 = params.gravity, params.stiffness, params.mass, params.leg_length
    s0 = np.asarray(state0, float)
    d = np.array([math.sin(theta) * math.cos(phi), math.sin(phi), -math.cos(theta) * math.cos(phi)])
    h_td = -l0 * d[2]
    t1 = math.sqrt(2 * (s0[2] - h_td) / g)  # fall from TOF to the touchdown height
    p_td = s0[:3] + s0[3:] * t1 - 0.5 * g * t1**2 * np.array([0, 0, 1.0])
    v_td = s0[3:] - g * t1 * np.array([0, 0, 1.0])
    foot = p_td + l0 * d

    def rhs(t, s):
        r = s[:3] - foot
        L = np.linalg.norm(r)
        return np.concatenate([s[3:], k / m * (l0 - L) * r / L - np.array([0, 0, g])])

    def lift(t, s):
        return np.linalg.norm(s[:3] - foot) - l0

    lift.terminal, lift.direction = True, 1
    st = solve_ivp(rhs, (0, 2.0), np.concatenate([p_td, v_td]), method="Radau", rtol=1e-12, atol=1e-13, events=lift)
    s_lo = st.y_events[0][0]
    t2 = s_lo[5] / g  # rise to the next TOF
    p1 = s_lo[:3] + s_lo[3:] * t2 - 0.5 * g * t2**2 * np.array([0, 0, 1.0])
    v1 = s_lo[3:] - g * t2 * np.array([0, 0, 1.0])
    return np.concatenate([p1, v1]), foot, (t1, st.t_events[0][0], t2)


def test_half_cycle_is_periodic_after_mirror_map(gait):
    hc = gait.half_cycle
    s0 = hc.state0
    s1, foot, (t1, ts, t2) = _independent_half_cycle(s0, hc.theta, hc.phi)
    # the mirror map about the mid-line y = 0: (x, y, z, vx, vy, vz) -> (x, -y, z, vx, -vy, vz)
    mirrored = s1 * np.array([1, -1, 1, 1, -1, 1])
    np.testing.assert_allclose(mirrored[1:], s0[1:], atol=1e-6)
    assert abs(s0[5]) < 1e-12 and abs(s0[3] - 3.5) < 1e-12
    # the module's own event times and foot agree with the independent integration
    np.testing.assert_allclose([hc.t_touchdown, hc.stance_duration, hc.flight_after], [t1, ts, t2], atol=1e-7)
    np.testing.assert_allclose(hc.foot, foot, atol=1e-7)
    assert abs(foot[1] + 0.1) < 1e-6  # step width w = 0.1 m to the right
    assert abs(hc.flight_duration - 0.2) < 1e-6


def test_full_cycle_on_the_other_foot_returns_to_the_start(gait):
    """The mirrored half cycle (left foot: phi -> -phi) closes the stride: a true period of two steps."""
    hc = gait.half_cycle
    s1, _, _ = _independent_half_cycle(hc.state0, hc.theta, hc.phi)
    s2, foot2, _ = _independent_half_cycle(s1, hc.theta, -hc.phi)
    np.testing.assert_allclose(s2[1:], hc.state0[1:], atol=1e-6)
    assert abs(foot2[1] - 0.1) < 1e-6
    step = s1[0] - hc.state0[0]
    assert abs((s2[0] - hc.state0[0]) - 2 * step) < 1e-6


def test_slip_integration_conserves_energy(gait):
    hc = gait.half_cycle
    g, k, m, l0 = P.gravity, P.stiffness, P.mass, P.leg_length
    t = np.linspace(0.0, hc.t_end, 2001)
    s = hc.sample(t)
    L = np.linalg.norm(s[:, :3] - hc.foot, axis=1)
    in_stance = (t > hc.t_touchdown) & (t < hc.t_liftoff)
    spring = np.where(in_stance, 0.5 * k * (l0 - L) ** 2, 0.0)
    E = 0.5 * m * np.sum(s[:, 3:] ** 2, axis=1) + m * g * s[:, 2] + spring
    assert np.max(np.abs(E - E[0])) / abs(E[0]) < 1e-6
    # the leg really is compressed in stance (L < l0) and the spring carries energy
    assert np.all(L[in_stance] < l0) and spring.max() > 0.05 * E[0]
    np.testing.assert_allclose(slip.energy(P, s[in_stance], hc.foot), E[in_stance], rtol=1e-12)


def test_flight_is_ballistic(gait):
    hc = gait.half_cycle
    t = np.linspace(0.0, hc.t_touchdown, 50)
    s = hc.sample(t)
    expect = hc.state0[:3] + np.outer(t, hc.state0[3:]) - 0.5 * P.gravity * np.outer(t**2, [0, 0, 1])
    np.testing.assert_allclose(s[:, :3], expect, atol=1e-9)


def test_touchdown_happens_at_the_leg_angle_geometry(gait):
    hc = gait.half_cycle
    d = slip.leg_direction(hc.theta, hc.phi)
    assert abs(np.linalg.norm(d) - 1) < 1e-15
    np.testing.assert_allclose(hc.touchdown[:3] + P.leg_length * d, hc.foot, atol=1e-9)
    assert abs(np.linalg.norm(hc.liftoff[:3] - hc.foot) - P.leg_length) < 1e-9
    assert hc.touchdown[5] < 0 < hc.liftoff[5]


def test_tvlip_deviation_is_small_vs_half_cycle_displacement(cmp):
    dx = cmp.displacement[0]
    assert 1.2 < dx < 1.6  # 3.5 m/s over about 0.4 s
    # x and y deviations: a few percent of the forward displacement at most (measured: 2.1 %, 0.2 %)
    assert cmp.max_deviation[0] < 0.04 * dx
    assert cmp.max_deviation[1] < 0.01 * dx
    # the first flight is the same parabola in both models (same TOF state)
    first = cmp.t < cmp.gait.half_cycle.t_touchdown
    np.testing.assert_allclose(cmp.tvlip_pos[first], cmp.slip_pos[first], atol=1e-9)


def test_tvlip_vertical_is_periodic_with_slip_timings(cmp):
    """T_r from eqs. (9)-(11) on the SLIP's h, tau_SS, tau_F returns the TV-LIPM CoM to the TOF height."""
    hc = cmp.gait.half_cycle
    assert abs(cmp.tvlip_pos[-1, 2] - hc.state0[2]) < 1e-9
    assert abs(cmp.tvlip_end_defect[3]) < 1e-9  # v_z = 0 at the TV-LIPM's TOF too
    # v_r is the touchdown vertical velocity: -g tau_F / 2, which is also the SLIP's (-g t_touchdown)
    assert abs(cmp.v_r + P.gravity * cmp.flight / 2) < 1e-9
    assert abs(cmp.v_r - hc.touchdown[5]) < 1e-6


def test_tvlip_stance_satisfies_eq1_by_finite_differences(cmp):
    hc = cmp.gait.half_cycle
    t0, t1 = hc.t_touchdown, hc.t_liftoff
    t = np.linspace(t0 + 0.01, t1 - 0.01, 7)
    eps = 1e-4
    tt = np.concatenate([t - eps, t, t + eps])
    p, _ = tvlip_half_cycle(hc.state0[:3], hc.state0[3:], hc.foot, t0, t1, cmp.T_r, tt, P.gravity)
    pm, pc, pp = p[:7], p[7:14], p[14:]
    acc = (pp - 2 * pc + pm) / eps**2
    expect = (pc - hc.foot) / cmp.T_r**2 - np.array([0, 0, P.gravity])
    np.testing.assert_allclose(acc, expect, atol=1e-4)


def test_reported_numbers_satisfy_the_running_stiffness_identities(cmp):
    """The JSON report is the physics of the run: T_r carries the vertical CoM from touchdown (h, v_r)
    back to (h, -v_r) over tau_SS (closed-form solution of z'' = z / T_r^2 - g, recomputed here),
    v_r = -g tau_F / 2, the SLIP timings add up to the half cycle, and the deviations are the ones of
    the samples."""
    d = cmp.as_dict()
    json.dumps(d, allow_nan=False)
    tv, sl = d["tvlip"], d["slip"]
    T, h, v_r, tss, tf = tv["T_r_s"], tv["h_m"], tv["v_r_m_per_s"], tv["tau_SS_s"], tv["tau_F_s"]
    g = sl["gravity"]
    a0, c, s = h - g * T**2, math.cosh(tss / T), math.sinh(tss / T)
    z_lo = g * T**2 + a0 * c + T * v_r * s
    vz_lo = a0 / T * s + v_r * c
    assert abs(z_lo - h) < 1e-9 and abs(vz_lo + v_r) < 1e-9
    assert abs(v_r + g * tf / 2) < 1e-12
    assert abs(sl["stance_s"] + sl["flight_s"] - sl["half_cycle_s"]) < 1e-12
    assert (tss, tf, h) == (sl["stance_s"], sl["flight_s"], sl["touchdown_height_m"])
    dev = np.max(np.abs(cmp.slip_pos - cmp.tvlip_pos), axis=0)
    np.testing.assert_allclose(list(d["max_deviation_m"].values()), dev, rtol=0, atol=0)
    tm = d["timing"]
    assert all(math.isfinite(tm[k]) and tm[k] > 0 for k in ("slip_optimise_and_integrate_s", "tvlip_T_r_solve_s"))


def test_bad_inputs_raise_gaitshift_errors():
    with pytest.raises(InputError):
        slip.periodic_half_cycle(-1.0)
    with pytest.raises(InputError):
        slip.periodic_half_cycle(3.5, flight=0.0)
    with pytest.raises(InputError):
        slip.SlipParams(stiffness=-5.0)
    with pytest.raises(InfeasibleError):
        slip.simulate_half_cycle(P, [0, 0, 0.5, 3.0, 0, 0], 0.3, 0.0)  # TOF below the touchdown height


def test_cli_compare_slip_writes_figure_and_json(tmp_path, capsys):
    from gaitshift.cli import main

    with pytest.raises(SystemExit) as ex:
        main(["compare-slip", "--out", str(tmp_path / "o"), "--repeats", "1"])
    assert ex.value.code == 0
    data = json.loads((tmp_path / "o" / "slip_compare.json").read_text())
    assert set(data["max_deviation_m"]) == {"x", "y", "z"}
    assert (tmp_path / "o" / "fig9_slip.png").stat().st_size > 10_000
    with pytest.raises(SystemExit) as ex:
        main(["compare-slip", "--out", str(tmp_path / "bad"), "--speed", "0"])
    assert ex.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("gaitshift: error:")
    assert not (tmp_path / "bad").exists()


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    z0=st.floats(1.0, 1.15),
    vx=st.floats(1.0, 5.0),
    vy=st.floats(-0.3, 0.3),
    theta=st.floats(0.1, 0.4),
    phi=st.floats(-0.12, 0.12),
)
def test_any_half_cycle_conserves_energy_and_vertical_angular_momentum(z0, vx, vy, theta, phi):
    """Non-periodic half cycles too: the spring is central about the foot and gravity is vertical, so
    E and the vertical angular momentum about the foot, (r x v)_z, are constants of the stance."""
    try:
        hc = slip.simulate_half_cycle(P, [0.0, 0.0, z0, vx, vy, 0.0], theta, phi, dense=True)
    except InfeasibleError:
        assume(False)
    t = np.linspace(0.0, hc.t_end, 600)
    s = hc.sample(t)
    E = slip.energy(P, s, hc.foot)
    assert np.max(np.abs(E - E[0])) < 1e-8 * E[0]
    stance = (t > hc.t_touchdown) & (t < hc.t_liftoff)
    r = s[stance, :3] - hc.foot
    Lz = r[:, 0] * s[stance, 4] - r[:, 1] * s[stance, 3]
    assert np.ptp(Lz) < 1e-8 * max(1.0, np.max(np.abs(Lz)))
    assert abs(hc.state1[5]) < 1e-9 and hc.state1[2] > hc.liftoff[2]


def test_calibrated_leg_reproduces_paper_table1_timings():
    """calibrate() picks (k, l0) so that the 3.5 m/s gait has h = 0.95 m and tau_SS = 0.2 s (Table I of
    paper 001); checked on an independent re-integration of the resulting gait."""
    p = slip.calibrate(3.5, flight=0.2, height=0.95, stance=0.2)
    g = slip.periodic_half_cycle(3.5, flight=0.2, params=p)
    hc = g.half_cycle
    _, _, (t1, ts, t2) = _independent_half_cycle(hc.state0, hc.theta, hc.phi, params=p)
    assert abs(p.leg_length * math.cos(hc.theta) * math.cos(hc.phi) - 0.95) < 1e-7
    assert abs(ts - 0.2) < 1e-6 and abs(t1 + t2 - 0.2) < 1e-6
    # the rounded defaults are the same leg to the stated digits
    assert abs(p.stiffness - P.stiffness) < 50 and abs(p.leg_length - P.leg_length) < 5e-4


def test_slip_benchmark_quick_run_produces_complete_rows():
    """The smoke run of the slip topic: every row has finite times and its baseline (never judged)."""
    from gaitshift import bench

    rows = [r for r in bench.run(quick=True, only=["slip"]) if "SLIP" in (r.baseline or "")]
    assert len(rows) == 3
    for r in rows:
        assert np.isfinite(r.median_s) and np.isfinite(r.p99_s) and r.median_s <= r.p99_s
        assert r.baseline_median_s is not None and np.isfinite(r.baseline_median_s)
    data = json.loads(bench.to_json(rows, quick=True))
    assert data["quick"] is True and len(data["results"]) == 3
