"""Contact from the motors' torques, eq. (2) of :mod:`gaitshift.control.estimation.torque_contact`.

The oracle is eq. (1) itself: the whole-body QP's solution satisfies the equations of motion with its
torques, its accelerations and its contact wrenches, so eq. (2) on those torques and accelerations
must give back the QP's normal forces (to the QP's tolerance), in double support at rest and in
single support mid-walk (the swing sole then reads zero). With the torques of a robot hanging in the
air (gravity compensation of the free legs only, nothing on the soles) both soles read zero. The
leg dofs are the chain from the sole to the floating base.
"""

from __future__ import annotations

from dataclasses import replace

import mujoco
import numpy as np
import pytest

from gaitshift.control.controller import Controller
from gaitshift.control.estimation.joints import JointVelocityFilter
from gaitshift.control.estimation.torque_contact import TorqueContact, leg_dofs, second_difference_variance
from gaitshift.control.frames import SensorFrame
from gaitshift.robots.config import load_robot
from gaitshift.wholebody.scaling import scale_scenario


def _frame(c: Controller, t: float, q: np.ndarray, dq: np.ndarray) -> SensorFrame:
    """The exact frame of the state (q, dq) of the controller's own model (IMU at its site)."""
    m = c.robot.model
    d = mujoco.MjData(m)
    d.qpos[:], d.qvel[:] = q, dq
    mujoco.mj_forward(m, d)
    idx = m.jnt_qposadr[m.actuator_trnid[:, 0]]
    vdx = m.jnt_dofadr[m.actuator_trnid[:, 0]]
    site = m.site(c.imu_site).id
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, d.site_xmat[site])
    up = d.site_xmat[site].reshape(3, 3).T @ np.array([0.0, 0.0, 9.81])
    return SensorFrame(t, quat, np.zeros(3), up, q[idx].copy(), dq[vdx].copy(), np.zeros(m.nu), np.full(2, 160.0))


def _in_the_air(ctrl: Controller, damping: bool = True):
    """The controller's robot model without the joints' dry friction (and damping unless ``damping``),
    and a state of it 0.5 m above its start pose (the controller's model has no floor)."""
    import copy

    m = copy.copy(ctrl.robot.model)
    m.dof_frictionloss[:] = 0.0
    if not damping:
        m.dof_damping[:] = 0.0
    d = mujoco.MjData(m)
    d.qpos[:] = ctrl.initial_qpos()
    d.qpos[2] += 0.5
    return replace(ctrl.robot, model=m), d


@pytest.fixture(scope="module")
def ctrl():
    return Controller.from_scenario("g1-walk", state="oracle")


def test_the_legs_are_the_chains_from_the_soles_to_the_base(ctrl):
    m = ctrl.robot.model
    for sole, dofs in zip(ctrl.robot.soles, TorqueContact(ctrl.robot).legs, strict=True):
        assert len(dofs) == 6  # the G1's legs
        bodies = {int(m.jnt_bodyid[m.dof_jntid[d]]) for d in dofs}
        b = sole.body
        chain = set()
        while b != ctrl.robot.pelvis_body:
            chain.add(b)
            b = int(m.body_parentid[b])
        assert bodies <= chain
    assert len(leg_dofs(m, ctrl.robot.pelvis_body)) == 0


@pytest.mark.parametrize("robot", ["g1", "h1", "t1"])  # legs of six joints (one batched solve), five and seven
def test_eq2_gives_back_the_qp_forces_at_rest(robot):
    from gaitshift.control.frames import OracleState

    c = Controller.from_scenario(scale_scenario("g1-walk", load_robot(robot)), state="oracle")
    q0 = c.initial_qpos()
    frame = _frame(c, 0.0, q0, np.zeros(c.robot.model.nv))
    truth = OracleState(q0, np.zeros(c.robot.model.nv), np.ones(2, bool), np.zeros((2, 2)))
    cmd = c.tick(SensorFrame(**{**frame.__dict__, "oracle": truth}))
    info = c.record.info
    f = TorqueContact(c.robot).normal_forces(c.state.cdata, cmd.tau, info.qdd)
    np.testing.assert_allclose(f, info.forces[:, 2], rtol=1e-5, atol=1e-3)
    weight = c.robot.mass * 9.81
    assert f.sum() == pytest.approx(weight, rel=0.02)


def test_eq4_gives_back_the_qp_centres_of_pressure_at_rest(ctrl):
    """The QP's solution satisfies eq. (1) with its torques, accelerations and contact wrenches, so eq. (4)
    on those torques and accelerations gives back the centres of pressure of the QP's wrenches (level
    soles at rest: the sole frames are the world's axes), inside the soles."""
    from gaitshift.control.frames import OracleState

    c = Controller.from_scenario("g1-walk", state="oracle")
    q0, nv = c.initial_qpos(), c.robot.model.nv
    still = OracleState(q0, np.zeros(nv), np.ones(2, bool), np.zeros((2, 2)))
    cmd = c.tick(SensorFrame(**{**_frame(c, 0.0, q0, np.zeros(nv)).__dict__, "oracle": still}))
    info = c.record.info
    _, cop = TorqueContact(c.robot).sole_loads(c.state.cdata, cmd.tau, info.qdd)
    for s in (0, 1):
        np.testing.assert_allclose(cop[s], info.cop_offset(s), atol=1e-5)
    assert np.all(np.abs(cop) <= 0.5 * np.asarray(c.robot.robot.sole_size))


def test_a_robot_in_the_air_reads_no_sole_force(ctrl):
    """Random torques and velocities with nothing on the soles: eq. (2) on MuJoCo's forward-dynamics
    accelerations reads zero on both soles. The joints' dry friction (a constraint force eq. (1) leaves
    out) is switched off for the identity, and with it on the error stays within its bound."""
    robot, d = _in_the_air(ctrl)
    m = robot.model
    rng = np.random.default_rng(3)
    d.qvel[:] = rng.normal(0.0, 0.3, m.nv)
    tau = rng.normal(0.0, 5.0, m.nu)
    d.ctrl[:] = tau
    mujoco.mj_forward(m, d)  # contacts: none (no floor in the controller's model)
    qdd = d.qacc.copy()
    f, cop = TorqueContact(robot).sole_loads(d, tau, qdd)
    np.testing.assert_allclose(f, 0.0, atol=1e-6)
    assert np.isnan(cop).all()  # no load, no centre of pressure
    d2 = mujoco.MjData(ctrl.robot.model)  # the model as shipped: 0.3 N m of dry friction per leg joint
    d2.qpos[:], d2.qvel[:], d2.ctrl[:] = d.qpos, d.qvel, tau
    mujoco.mj_forward(ctrl.robot.model, d2)
    f2 = TorqueContact(ctrl.robot).normal_forces(d2, tau, d2.qacc.copy())
    assert np.all(np.abs(f2) < 5.0)  # newtons: the friction torques over the legs' lever arms


def test_the_window_differentiates_a_constant_acceleration_exactly():
    """Joint angles and base velocity of a motion with constant accelerations (quadratic angles,
    linear velocities): the window's centre acceleration is exact, and the torque is the triangular
    mean about the centre (a torque rising by one per tick reads the centre's), also after the window
    has moved on past its first ticks."""
    from gaitshift.control.estimation.torque_contact import AccelerationWindow

    n, dt, nj = 3, 0.002, 4
    acc_true = np.array([0.5, -1.0, 2.0, 0.1, 0.2, -0.3, 3.0, -2.0, 1.5, 0.25])
    w = AccelerationWindow(n, dt)
    for k in range(2 * n + 4):  # three ticks more than the window holds: the oldest drop out
        t = k * dt
        qpos = np.zeros(7 + nj)
        qpos[7:] = 0.5 * acc_true[6:] * t * t + 0.1 * t
        qvel = np.zeros(6 + nj)
        qvel[:6] = acc_true[:6] * t
        w.push(qpos, qvel, np.full(2, float(k)))
    assert w.full
    np.testing.assert_allclose(w.acceleration(), acc_true, rtol=1e-6, atol=1e-8)
    np.testing.assert_allclose(w.mean_torque(), np.full(2, float(n + 3)))  # the centre is tick n + 3
    assert w.weights.sum() == pytest.approx(1.0)


def test_a_torque_step_inside_the_window_reads_no_sole_force(ctrl):
    """The robot in the air (the controller's model has no floor), stepped by MuJoCo under torques that
    jump every few ticks (as at a planned touch-down or lift-off): eq. (2) on the window's accelerations
    and torques reads no sole force, since both are the same weighted mean of eq. (1) (joint damping and
    dry friction off for the identity). A uniform mean of the torques reads a torque step as a force."""
    from gaitshift.control.estimation.torque_contact import AccelerationWindow

    robot, d = _in_the_air(ctrl, damping=False)
    m = robot.model
    rng = np.random.default_rng(5)
    n = 5
    window, contact = AccelerationWindow(n, m.opt.timestep), TorqueContact(robot)
    worst = {"triangular": 0.0, "uniform": 0.0}
    tau = np.zeros(m.nu)
    for k in range(8 * n):
        if k % 3 == 0:
            tau = rng.normal(0.0, 3.0, m.nu)
        state = (d.qpos.copy(), d.qvel.copy())
        d.ctrl[:] = tau
        mujoco.mj_step(m, d)
        window.push(*state, d.actuator_force.copy())  # the state and the torque that moved it on
        if not window.full:
            continue
        centre = window.centre_data(m)
        acc = window.acceleration()
        triangular = contact.normal_forces(centre, window.mean_torque(), acc)
        worst["triangular"] = max(worst["triangular"], *np.abs(triangular))
        uniform = np.mean(window.tau[1:], axis=0)
        worst["uniform"] = max(worst["uniform"], *np.abs(contact.normal_forces(centre, uniform, acc)))
    assert worst["triangular"] < 1.0  # newtons: M, b and J vary a little over the window
    assert worst["uniform"] > 10 * worst["triangular"]


@pytest.mark.parametrize("n", [5, 10])
def test_eq3_is_the_variance_of_the_windows_second_difference(n):
    """Monte Carlo: white encoder and driver readings of still joints through the joint filter; the
    second difference ``q_{c+n} - 2 q_c + q_{c-n}`` of the filtered angles has eq. (3)'s variance (5 %)."""
    rng = np.random.default_rng(1)
    dt, pos_std, vel_std, joints, ticks = 0.002, 0.0058, 0.87, 50, 4000
    jf = JointVelocityFilter(joints, dt, pos_std, vel_std, 100.0)
    jf.reset(np.zeros(joints))
    q = np.array([jf.update(rng.normal(0, pos_std, joints), rng.normal(0, vel_std, joints))[0] for _ in range(ticks)])
    q = q[500:]
    d2 = q[2 * n :] - 2 * q[n:-n] + q[: -2 * n]
    want = second_difference_variance(jf.a, jf.gain, np.diag([pos_std**2, vel_std**2]), n)
    assert d2.var() == pytest.approx(want, rel=0.05)


@pytest.mark.parametrize(("noise", "point"), [("typical", "cop"), ("rl-peer", "centre")])
def test_the_centre_of_pressure_is_the_stance_point_only_where_its_noise_is_small(noise, point):
    """Eq. (3) carried through eq. (4): the CoP's std per sample at half the weight, from the moments'
    acceleration gains and the window's second-difference variance, is 1.4 mm for ``typical`` encoders and
    about 1 cm for ``rl-peer`` (+-0.01 rad); the controller takes the CoP as the stance point below
    ``COP_STD_MAX`` of the sole's length, else the sole's centre."""
    from gaitshift.control.state import COP_STD_MAX, torque_window

    c = Controller.from_scenario("g1-walk", noise=noise)
    assert c.state.stance_point == point
    n, _, cop_std = torque_window(c.state.torque_contact, c.initial_qpos(), c.state.estimator.tuning)
    length = c.robot.robot.sole_size[0]
    assert (cop_std <= COP_STD_MAX * length) == (point == "cop")
    assert 1e-3 < cop_std < 2e-2 and n >= 5
