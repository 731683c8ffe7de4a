"""The controller is one component: built from a scenario alone, ticked with frames alone.

It proves: ``Controller.from_scenario`` needs no world (its model has no floor and no sensors of the
simulation); its host interface names the motors in the model's actuator order and the IMU site of the
model; the pose it starts in puts the soles on the plan's first footholds; a frame of the wrong size
or with a NaN is one ``InputError`` naming the field; the first tick at rest commands torques that
hold the robot up (the vertical force on the base equals the weight, Newton's law at rest); a live
command on a live-command plan reaches the generator, and on an offline plan is refused; the oracle
controller refuses a frame without the oracle state; no module of ``control/`` imports the simulation.
"""

from __future__ import annotations

import ast
from pathlib import Path

import mujoco
import numpy as np
import pytest

import gaitshift
from gaitshift.control.controller import Controller
from gaitshift.control.frames import MotorCommand, SensorFrame
from gaitshift.errors import InputError
from standing import rest_frame

CONTROL = Path(gaitshift.__file__).parent / "control"


@pytest.fixture(scope="module")
def ctrl():
    return Controller.from_scenario("g1-walk")


def _rest_frame(c: Controller) -> SensorFrame:
    """The frame a robot at rest in the start pose reports (exact sensors)."""
    return rest_frame(c)


def test_the_host_interface_comes_from_the_model(ctrl):
    m = mujoco.MjModel.from_xml_path(str(ctrl.mjcf_path))
    names = ctrl.motor_names
    assert len(names) == ctrl.robot.model.nu == m.nu
    hinges = [m.joint(j).name for j in range(m.njnt) if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE]
    assert list(names) == hinges  # one motor per hinge, in model order
    assert mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, ctrl.imu_site) >= 0
    assert ctrl.period == pytest.approx(0.002)
    assert ctrl.initial_qpos().shape == (m.nq,)
    # its own model: no floor, no touch sensors of the simulated world
    planes = ctrl.robot.model.geom_type == mujoco.mjtGeom.mjGEOM_PLANE
    assert not planes.any() and ctrl.robot.model.nsensor == m.nsensor


def test_the_start_pose_stands_on_the_first_footholds(ctrl):
    m = ctrl.robot.model
    d = mujoco.MjData(m)
    d.qpos[:] = ctrl.initial_qpos()
    mujoco.mj_kinematics(m, d)
    mujoco.mj_comPos(m, d)
    feet = np.array([ctrl.robot.sole_frame(d, s)[0] for s in (0, 1)])
    np.testing.assert_allclose(feet, ctrl.trajectory.foot_pos[0], atol=2e-3)
    np.testing.assert_allclose(d.subtree_com[0], ctrl.trajectory.com_pos[0], atol=2e-3)


@pytest.mark.parametrize(
    ("field", "value"),
    [("q", np.zeros(3)), ("dq", [np.nan] * 29), ("imu_quat", [0.0, 0.0, 0.0, 0.0]), ("imu_gyro", "fast"),
     ("t", -1.0), ("foot_force", [1.0, 2.0, 3.0]), ("depth_points", np.zeros((4, 2))),
     ("depth_points", [[0.0, np.inf, 1.0]]), ("depth_points", "cloud")],
)  # fmt: skip
def test_a_bad_frame_is_one_input_error_naming_its_field(ctrl, field, value):
    good = _rest_frame(ctrl)
    fields = {k: getattr(good, k) for k in ("t", "imu_quat", "imu_gyro", "imu_acc", "q", "dq", "tau_est", "foot_force")}
    with pytest.raises(InputError) as info:
        SensorFrame.checked(29, **(fields | {field: value}))
    assert info.value.field == f"SensorFrame.{field}"
    with pytest.raises(InputError, match="SensorFrame"):
        Controller.from_scenario("g1-walk").tick(SensorFrame(**(fields | {"q": np.zeros(3)})))


def test_the_first_tick_at_rest_holds_the_weight():
    """Newton at rest: the torques' base rows vanish, so the contact forces the QP plans carry the weight."""
    c = Controller.from_scenario("g1-walk")
    cmd = c.tick(_rest_frame(c))
    assert isinstance(cmd, MotorCommand) and cmd.tau.shape == (c.robot.model.nu,)
    assert np.all(cmd.kp == 0) and np.all(cmd.kd == 0)  # torque control
    assert np.all(np.abs(cmd.tau) <= c.robot.torque_limit + 1e-9)
    rec = c.record
    assert rec is not None and rec.info.ok
    weight = c.robot.mass * float(-c.robot.model.opt.gravity[2])
    assert rec.info.forces[:, 2].sum() == pytest.approx(weight, rel=0.02)


def test_live_commands_reach_a_live_plan_and_are_refused_by_an_offline_one(ctrl):
    live = Controller.from_scenario("g1-tour")
    live.command(0.4, 0.0, 0.1)
    np.testing.assert_allclose(live.driver.gen.command_velocity, [0.4, 0.0, 0.1])  # within the G1's limits
    with pytest.raises(InputError, match="command"):
        ctrl.command(0.3, 0.0, 0.0)
    with pytest.raises(InputError, match="stop"):
        ctrl.stop()


def test_an_oracle_controller_refuses_a_frame_without_the_truth():
    c = Controller.from_scenario("g1-walk", state="oracle")
    with pytest.raises(InputError, match=r"SensorFrame\.oracle"):
        c.tick(_rest_frame(c))


def test_no_module_of_control_imports_the_simulation_or_steps_physics():
    for path in CONTROL.rglob("*.py"):
        tree = ast.parse(path.read_text())
        names = [n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)]
        names += [a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names]
        assert not [n for n in names if n.startswith(("gaitshift.sim", "gaitshift.cli", "gaitshift.campaign"))], path
        calls = {n.attr for n in ast.walk(tree) if isinstance(n, ast.Attribute)}
        assert not calls & {"mj_step", "mj_step1", "mj_step2", "mj_contactForce"}, path


def test_a_controller_with_torque_contact_ticks_on_frames_without_foot_force():
    """The robot without sole force sensors (the G1: its YAML's ``sensors.foot_force`` is false, the
    default of its controller): the frame carries none, and the controller reads its sole forces from
    the motors' torques; one with force contact refuses such a frame, naming the field."""
    c = Controller.from_scenario("g1-walk")
    assert c.state.torque_contact is not None
    frame = _rest_frame(c)
    bare = SensorFrame(**{**frame.__dict__, "foot_force": None})
    for k in range(3):
        cmd = c.tick(SensorFrame(**{**bare.__dict__, "t": k * c.period}))
        assert np.all(np.isfinite(cmd.tau))
    f = Controller.from_scenario("g1-walk", contact="force")
    assert f.state.torque_contact is None
    f.tick(frame)
    with pytest.raises(InputError, match=r"SensorFrame\.foot_force"):
        f.tick(SensorFrame(**{**bare.__dict__, "t": c.period}))


def test_a_live_plans_look_ahead_is_not_the_end_of_the_run():
    """A live plan is tracked as a look-ahead a few steps long: past its last sample the run goes on (a re-plan
    off the tick may come late), while the run's last plan, the robot at rest, ends it."""
    live = Controller.from_scenario("g1-tour", replan="inline")
    assert live.traj.meta["open_end"] and live.traj.t[-1] < 10.0  # the tour lasts 26 s and more
    assert not live.finished(float(live.traj.t[-1]) + 1.0)
    whole = gaitshift.plan("g1-tour")  # the run planned to its end: the robot at rest
    assert not whole.meta.get("open_end", False)
    offline = Controller.from_scenario("g1-walk")
    assert offline.finished(float(offline.traj.t[-1]) + 0.01) and not offline.finished(float(offline.traj.t[-1]))


@pytest.mark.parametrize(
    ("scenario", "settings", "floor"),
    [
        ("g1-walk", {}, None),  # not told: the default
        ("g1-walk", {"known_floor": True}, 0.0),  # no terrain, no bumps: the flat floor, told
        ("g1-stairs-up", {"known_floor": True}, None),  # terrain: no flat floor to pin
    ],
)
def test_a_scenario_on_the_flat_floor_tells_the_estimator_its_height_when_asked(scenario, settings, floor):
    ctrl = Controller.from_scenario(scenario, **settings)
    assert ctrl.state.estimator is not None
    assert ctrl.state.estimator.filter.floor == floor


def test_the_scenarios_sim_block_tells_the_floor_unless_the_world_has_bumps(tmp_path):
    walk = (Path(gaitshift.__file__).parent / "scenario" / "builtin" / "g1-walk.yaml").read_text()
    for extra, floor in (("", 0.0), ("  bumps: [{x: 1.0, height: 0.02}]\n", None)):
        path = tmp_path / "walk.yaml"
        path.write_text(walk + "sim:\n  known_floor: true\n" + extra)
        assert Controller.from_scenario(path).state.estimator.filter.floor == floor
    with pytest.raises(InputError, match="known_floor"):
        Controller.from_scenario("g1-walk", known_floor="yes")
