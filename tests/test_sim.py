"""Closed loop on the simulated G1: plant, inverse-dynamics identities, and full runs.

Physics oracles: the rated torque limits are read from the MJCF text independently of the plant
builder; the QP's (qdd, f, tau) must satisfy the equations of motion as recomputed by MuJoCo's
recursive Newton-Euler (``mj_rne``), a different code path from the mass matrix the QP uses; the
contact forces of a standing robot must carry its weight (Newton); the full runs must not fall and
must track the CoM height within the issue's 1.5 cm RMS bound.
"""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

import gaitshift  # noqa: E402
from gaitshift.sim.controller import TickReference, WholeBodyController  # noqa: E402
from gaitshift.sim.loop import SimOptions, mid_stance_pushes, simulate  # noqa: E402
from gaitshift.sim.plant import build_plant, g1_scene_path, standing_qpos  # noqa: E402


@pytest.fixture(scope="module")
def plant():
    return build_plant(0.002)


def test_plant_motors_are_limited_to_the_rated_joint_torques(plant):
    xml = g1_scene_path().with_name("g1.xml").read_text()
    rated = {j.get("name"): float(j.get("actuatorfrcrange").split()[1])
             for j in ET.fromstring(xml).iter("joint") if j.get("actuatorfrcrange")}
    m = plant.model
    assert m.nu == len(rated) == 29
    for i in range(m.nu):
        name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, m.actuator_trnid[i, 0])
        assert m.actuator_ctrlrange[i].tolist() == [-rated[name], rated[name]]
        assert m.actuator_biastype[i] == 0 and m.actuator_gainprm[i, 0] == 1.0  # pure torque motor
    assert m.opt.integrator == mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    assert m.opt.timestep == pytest.approx(0.002)


def _standing(plant):
    m = plant.model
    d = mujoco.MjData(m)
    q0 = standing_qpos(plant)
    d.qpos[:] = q0
    mujoco.mj_forward(m, d)
    mujoco.mj_subtreeVel(m, d)
    feet = np.array([plant.sole_frame(d, s)[0] for s in (0, 1)])
    return d, q0, feet


def test_qp_solution_satisfies_the_equations_of_motion_by_newton_euler(plant):
    d, q0, feet = _standing(plant)
    ctrl = WholeBodyController(plant, q0)
    com = d.subtree_com[0] + [0.01, 0.02, -0.01]  # an offset reference so that the solution is not trivial
    ref = TickReference(com, np.zeros(3), np.array([0.3, -0.5, 0.2]), np.array([True, True]), np.full(2, 1e4),
                        feet, np.zeros((2, 3)), np.zeros((2, 3)), np.zeros(2))
    tau, info = ctrl.compute(d, ref)
    assert info.ok
    rne = np.zeros(plant.model.nv)
    d.qacc[:] = info.qdd
    mujoco.mj_rne(plant.model, d, 1, rne)  # M qdd + bias, by recursive Newton-Euler
    rne += plant.model.dof_armature * info.qdd  # rotor inertia: in M (mj_crb) but not in the RNE tree
    gen = info.contact_jacobian.T @ info.contact_forces
    gen[plant.actuated_dofs] += tau
    np.testing.assert_allclose(rne - d.qfrc_passive, gen, atol=1e-6 * np.max(np.abs(rne)))
    f = info.contact_forces.reshape(-1, 3)
    assert np.all(f[:, 2] >= -1e-9)
    assert np.all(np.abs(f[:, :2]) <= ctrl.gains.mu * f[:, 2:3] + 1e-6)
    assert np.all(np.abs(tau) <= plant.torque_limit + 1e-9)


def test_standing_robot_contact_forces_carry_its_weight(plant):
    d, q0, feet = _standing(plant)
    m = plant.model
    ctrl = WholeBodyController(plant, q0)
    ref = TickReference(d.subtree_com[0].copy(), np.zeros(3), np.zeros(3), np.array([True, True]), np.full(2, 1e4),
                        feet, np.zeros((2, 3)), np.zeros((2, 3)), np.zeros(2))
    cf = np.zeros(6)
    totals = []
    for k in range(500):  # 1 s
        mujoco.mj_forward(m, d)
        mujoco.mj_subtreeVel(m, d)
        tau, info = ctrl.compute(d, ref)
        d.ctrl[:] = tau
        if k >= 250:
            fz = 0.0
            for i in range(d.ncon):
                mujoco.mj_contactForce(m, d, i, cf)
                fz += (d.contact[i].frame.reshape(3, 3).T @ cf[:3])[2]
            totals.append(fz)
        mujoco.mj_step(m, d)
    weight = plant.mass * 9.81
    assert np.mean(totals) == pytest.approx(weight, rel=0.01)
    assert abs(d.subtree_com[0, 2] - ref.com_pos[2]) < 0.005


def _check_run(result, traj, rms_bound=0.015):
    met = result.metrics
    assert not result.fell, met.get("fall_reason")
    assert met["steps_completed"] == met["steps_planned"]
    for gait in ("walk", "run"):
        if gait in met["com_rms"]:
            assert met["com_rms"][gait][2] <= rms_bound, (gait, met["com_rms"][gait])
    assert met["peak_torque_fraction"] <= 1.0 + 1e-9
    assert np.all(np.isfinite(result.arrays["qpos"]))
    # the logged torques are what MuJoCo applied: within the motor ctrlrange
    assert np.all(np.abs(result.arrays["tau"]) <= np.array(result.meta["torque_limit"]) + 1e-9)


def test_g1_walk_ten_steps_without_fall_and_com_height_within_1p5_cm(tmp_path):
    traj = gaitshift.plan("g1-walk")
    result = simulate(traj)
    _check_run(result, traj)
    # it ends at rest on its reference (the plan, translated by the capture-point corrections,
    # which stay within their 10 cm bound)
    a = result.arrays
    np.testing.assert_allclose(a["com_pos"][-1, :2], a["com_ref"][-1, :2], atol=0.02)
    assert np.linalg.norm(a["com_vel"][-1]) < 0.05
    assert result.metrics["max_shift"] <= 0.10 + 1e-9
    assert a["com_pos"][-1, 0] > 0.9 * traj.com_pos[-1, 0]  # and it did walk forward
    out = result.save(tmp_path / "sim.npz")
    with np.load(out) as z:
        for key in ("t", "qpos", "qvel", "tau", "com_pos", "com_ref", "com_vel", "com_vel_ref", "contact",
                    "contact_ref", "grf", "fell", "fall_time", "meta"):
            assert key in z.files
        assert z["grf"].shape == (len(z["t"]), 2, 3)
        assert not bool(z["fell"]) and float(z["fall_time"]) == -1.0
        for key in z.files:
            if z[key].dtype.kind == "f":
                assert np.all(np.isfinite(z[key])), key
        meta = json.loads(str(z["meta"]), parse_constant=lambda c: pytest.fail(f"{c} in meta"))
        assert meta["metrics"]["fell"] is False
        # measured vertical GRF averages to the weight over the whole walk (Newton, CoM starts and ends at rest)
        dt = z["t"][1] - z["t"][0]
        impulse = z["grf"][:, :, 2].sum() * dt
        assert impulse / (z["t"][-1] + dt) == pytest.approx(build_plant().mass * 9.81, rel=0.02)


SHORT_WRW = {
    "planner": "tvlip", "name": "short-walk-run-walk", "height": 0.62,
    "timing": {"single_support": 0.32, "double_support": 0.12, "flight": 0.12, "start": 0.8, "stop": 1.0},
    "foot": {"size": [0.17, 0.05], "zmp_margin": 0.01},
    "gait": [{"gait": "walk", "steps": 2}, {"gait": "run", "steps": 4}, {"gait": "walk", "steps": 2}],
    "profile": {"max_stride": 0.2, "accelerate_steps": 2, "decelerate_steps": 2, "step_width": 0.237},
    "swing_height": 0.06,
}


@pytest.fixture(scope="module")
def short_wrw():
    traj = gaitshift.plan(gaitshift.load_scenario(SHORT_WRW))
    return traj, simulate(traj)


def test_short_walk_run_walk_without_fall_and_com_height_within_1p5_cm(short_wrw):
    traj, result = short_wrw
    _check_run(result, traj)
    # the robot really left the ground: at least 70 % of the planned flight on average (issue 5)
    assert result.metrics["flight_ratio"] >= 0.7


def _flight_acc_error(result):
    a = result.arrays
    dt = a["t"][1] - a["t"][0]
    air = ~np.any(a["contact"], axis=1)
    inner = air[1:-1] & air[:-2] & air[2:]  # interior samples of the airborne intervals
    acc = ((a["com_vel"][2:] - a["com_vel"][:-2]) / (2 * dt))[inner]
    return inner.sum(), np.max(np.abs(acc - [0.0, 0.0, -9.81])), inner


def test_measured_flight_is_ballistic(short_wrw):
    """With both soles off the floor the only external force is gravity: the measured CoM
    acceleration (central differences of the logged CoM velocity) is (0, 0, -g), up to the
    integrator's discretisation (semi-implicit Euler conserves M(q_k) v, not M(q_k+1) v, an O(dt)
    error): halving the time step halves the deviation."""
    traj, result = short_wrw
    n, err2, inner = _flight_acc_error(result)
    assert n >= 30  # several flight phases were achieved
    assert err2 < 0.1
    assert np.all(result.arrays["grf_ref"][1:-1][inner] == 0.0)  # the QP planned no contact force
    n1, err1, _ = _flight_acc_error(simulate(traj, SimOptions(control_period=0.001)))
    assert n1 >= 60
    assert 0.3 < err1 / err2 < 0.7


def test_online_variable_speed_follows_commands_within_0p1_m_s():
    from gaitshift.sim.loop import OnlineReplanner

    sc = gaitshift.load_scenario("g1-online-variable-speed")
    rp = OnlineReplanner(sc)
    result = simulate(rp.trajectory, replanner=rp)
    met = result.metrics
    assert not result.fell, met.get("fall_reason")
    assert result.meta["replans"] >= 20  # one re-plan from the measured CoM per running step
    errs = met["speed_errors"]
    assert len(errs) >= 6
    assert max(abs(e[3]) for e in errs) <= 0.1
    assert met["com_rms"]["run"][2] <= 0.015


@pytest.mark.parametrize("name", ["g1-run", "g1-walk-run-walk"])
def test_builtin_running_scenario_completes_with_flight_and_height_tracking(name):
    if name not in gaitshift.builtin_names():
        pytest.skip(f"{name} not installed")
    traj = gaitshift.plan(name)
    result = simulate(traj)
    _check_run(result, traj)
    assert result.metrics["flight_ratio"] >= 0.7  # constant-speed running steps (issue 5)


def test_g1_push_recovery_survives_10_newton_seconds_and_not_100():
    traj = gaitshift.plan("g1-push-recovery")
    ok = simulate(traj, SimOptions(pushes=mid_stance_pushes(traj, 10.0)))
    assert not ok.fell, ok.metrics.get("fall_reason")
    # the pushes were applied: +10 N s then -10 N s laterally
    a = ok.arrays
    dt = a["t"][1] - a["t"][0]
    fy = a["push_force"][:, 1]
    assert fy[fy > 0].sum() * dt == pytest.approx(10.0, rel=1e-6)
    assert fy[fy < 0].sum() * dt == pytest.approx(-10.0, rel=1e-6)
    bad = simulate(traj, SimOptions(pushes=mid_stance_pushes(traj, 100.0)))
    assert bad.fell


def test_a_large_push_is_detected_as_a_fall():
    traj = gaitshift.plan("g1-walk")
    pushes = mid_stance_pushes(traj, 300.0, steps=(2,))
    result = simulate(traj, SimOptions(pushes=pushes))
    assert result.fell
    assert result.fall_time > pushes[0].t
    assert result.metrics["steps_completed"] < result.metrics["steps_planned"]


def test_simulate_cli_rejects_a_bad_output_suffix_with_one_line(tmp_path, capsys):
    from gaitshift.cli import main

    with pytest.raises(SystemExit) as exc:
        main(["simulate", "g1-walk", "--out", str(tmp_path / "sim.txt")])
    err = capsys.readouterr().err
    assert exc.value.code == 2
    assert len(err.strip().splitlines()) == 1 and "--out" in err
    assert not (tmp_path / "sim.txt").exists()
