"""Every shipped robot config loads from its YAML alone, and what is read from its model is physical:
the standing pose is statically balanced (CoM over the support polygon of the soles), the soles are
flat on one plane with upward normals, the torque limits are finite, and 5-DoF legs are detected."""

from __future__ import annotations

from importlib import resources

import mujoco
import numpy as np
import pytest
from scipy.spatial import ConvexHull, Delaunay

import gaitshift
from gaitshift.robots import builtin_robots, load_robot
from gaitshift.wholebody.scaling import scale_scenario

ROBOTS = ["g1", "t1", "h1", "op3", "berkeley"]


def test_the_five_robots_ship_a_config():
    assert set(ROBOTS) <= set(builtin_robots())


@pytest.mark.parametrize("name", ROBOTS)
def test_standing_pose_is_statically_balanced_with_flat_soles(name):
    robot = load_robot(name)
    m = robot.model()
    d = mujoco.MjData(m)
    d.qpos[:] = robot.standing_qpos(m)
    mujoco.mj_kinematics(m, d)
    mujoco.mj_comPos(m, d)
    points = []
    for side, site in enumerate(robot.SOLE_SITES):
        R = d.site_xmat[m.site(site).id].reshape(3, 3)
        assert R[2, 2] > np.cos(np.radians(1.0)), f"{name} sole {side} tilted"
        points.append(d.site_xpos[m.site(site).id] + robot.soles[side].points @ R.T)
    pts = np.vstack(points)
    assert np.ptp(pts[:, 2]) < 2e-3  # one sole plane
    hull = ConvexHull(pts[:, :2])
    assert Delaunay(pts[hull.vertices, :2]).find_simplex(d.subtree_com[1][:2]) >= 0
    assert robot.com_height > 0.5 * robot.leg_length


@pytest.mark.parametrize("name", ROBOTS)
def test_leg_torque_limits_are_finite_and_positive(name):
    robot = load_robot(name)
    legs = [robot.joint_names.index(j) for j in robot.leg_joints]
    assert np.all(np.isfinite(robot.torque_limit[legs])) and np.all(robot.torque_limit[legs] > 0)


def test_h1_legs_cannot_roll_their_feet_and_the_others_can():
    assert load_robot("h1").foot_roll == (False, False)
    for name in ("g1", "t1", "op3", "berkeley"):
        assert load_robot(name).foot_roll == (True, True)


def test_berkeley_sole_frame_from_its_foot_box_is_level_although_the_foot_link_is_not():
    robot = load_robot("berkeley")
    m = robot.model()
    d = mujoco.MjData(m)
    d.qpos[:] = robot.standing_qpos(m)
    mujoco.mj_kinematics(m, d)
    body = d.xmat[m.body(robot.sole_bodies[0]).id].reshape(3, 3)
    assert body[2, 2] < np.cos(np.radians(20.0))  # the link itself is rotated against the world
    assert d.site_xmat[m.site(robot.SOLE_SITES[0]).id].reshape(3, 3)[2, 2] > np.cos(np.radians(1.0))


def test_op3_servo_speed_bound_is_torque_over_damping_read_from_the_mjcf_text():
    """MJCF text: default joint damping 1.084 N m s/rad, position servos forcerange 5 N m: 4.61 rad/s."""
    import re

    robot = load_robot("op3")
    text = robot.mjcf.read_text()
    damping = float(re.search(r'<joint damping="([0-9.]+)"', text).group(1))
    force = float(re.search(r'forcerange="-?[0-9.]+ ([0-9.]+)"', text).group(1))
    assert np.allclose(robot.damping_speed, force / damping)
    assert np.allclose(robot.speed_limits()[0], force / damping) and np.all(np.isinf(robot.velocity_limit))
    assert np.all(np.isinf(load_robot("t1").speed_limits()[0]))  # no damping, no YAML limits: unchecked


def test_a_robots_gait_key_shortens_the_flight_and_sets_the_step_width(tmp_path):
    """``gait: {flight_scale, step_width}`` in a robot YAML: the scaled plan's flights last flight_scale x
    the scenario's and are ballistic (touchdown speed g T_f / 2, softer by the same factor); the lateral
    step width is the YAML's, not the standing foot separation."""
    text = (resources.files("gaitshift.robots") / "configs" / "t1.yaml").read_text()
    plain = text.split("\ngait:")[0]  # the shipped T1 without its own gait choices
    (tmp_path / "t1-plain.yaml").write_text(plain.replace("name: t1", "name: t1-plain"))
    soft = plain.replace("name: t1", "name: t1-soft") + "\ngait: {flight_scale: 0.5, step_width: 0.18}\n"
    (tmp_path / "t1-soft.yaml").write_text(soft)
    flights = {}
    for name in ("t1-plain", "t1-soft"):
        sc = scale_scenario("g1-walk-run-walk", str(tmp_path / f"{name}.yaml"))
        traj = gaitshift.plan(sc)
        air = ~traj.contact.any(axis=1)
        edge = np.diff(np.r_[0, air.astype(int), 0])
        start, end = np.flatnonzero(edge == 1), np.flatnonzero(edge == -1)
        durations = (end - start) * traj.dt
        assert len(start) == 10 and np.allclose(durations, sc.timing.flight)
        assert np.allclose(traj.com_vel[end - 1, 2], -traj.gravity * sc.timing.flight / 2, atol=0.02)
        flights[name] = (sc.timing.flight, sc.profile.step_width)
    assert flights["t1-soft"][0] == pytest.approx(0.5 * flights["t1-plain"][0])
    assert flights["t1-soft"][1] == 0.18
    assert flights["t1-plain"][1] == pytest.approx(load_robot(str(tmp_path / "t1-plain.yaml")).foot_separation)


def test_step_time_scale_makes_quicker_shorter_steps_with_the_lipm_lateral_sway(tmp_path):
    """``gait: {step_time_scale: s}``: support times and stride x s (speed kept), and the planned lateral
    CoM sway about the mid-line of the feet in steady walking is the LIPM's w (1 - 1/cosh(omega T / 2))
    (w = half the step width, T = single + double support, omega = sqrt(g / h)): shorter steps sway less."""
    text = (resources.files("gaitshift.robots") / "configs" / "h1.yaml").read_text()
    plain = "\n".join(line for line in text.splitlines() if not line.startswith("gait:"))
    (tmp_path / "h1-plain.yaml").write_text(plain.replace("name: h1", "name: h1-plain"))
    quick = load_robot("h1")
    assert quick.step_time_scale == 0.5 and load_robot(str(tmp_path / "h1-plain.yaml")).step_time_scale == 1.0
    sway = {}
    for robot in (str(tmp_path / "h1-plain.yaml"), quick):
        sc = scale_scenario("g1-walk", robot)
        traj = gaitshift.plan(sc)
        steady = (traj.t > 2.0) & (traj.t < 3.5)
        y = np.abs(traj.com_pos[steady, 1] - traj.foot_pos[steady, :, 1].mean(axis=1)).max()
        step = sc.timing.single_support + sc.timing.double_support
        omega = np.sqrt(sc.gravity / sc.height)
        assert y == pytest.approx(sc.profile.step_width / 2 * (1 - 1 / np.cosh(omega * step / 2)), rel=0.25)
        sway[sc.timing.single_support] = (y, sc.profile.max_stride / step)
    (y_quick, v_quick), (y_plain, v_plain) = sway[0.2], sway[0.4]
    assert y_quick < 0.45 * y_plain and v_quick == pytest.approx(v_plain)


def test_a_robots_ik_weights_replace_the_ik_defaults_and_unknown_ones_are_named(tmp_path):
    from gaitshift.errors import InputError
    from gaitshift.wholebody.ik import IKSettings, WholeBodyIK

    text = (resources.files("gaitshift.robots") / "configs" / "berkeley.yaml").read_text().split("\nik:")[0]
    (tmp_path / "b.yaml").write_text(text.replace("name: berkeley", "name: b") + "\nik: {posture_cost: 0.7}\n")
    ik = WholeBodyIK(str(tmp_path / "b.yaml"), IKSettings(torso_cost=3.0))
    assert (ik.settings.posture_cost, ik.settings.torso_cost) == (0.7, 3.0)
    assert WholeBodyIK("g1").settings == IKSettings()
    (tmp_path / "c.yaml").write_text(text.replace("name: berkeley", "name: c") + "\nik: {max_iter: 3.0}\n")
    with pytest.raises(InputError, match=r"robot\.ik\.max_iter"):
        load_robot(str(tmp_path / "c.yaml"))


def test_a_robots_gait_key_caps_the_stride_and_sets_the_swing_height(tmp_path):
    """``gait: {max_stride, swing_height}``: the scaled plan's longest step is the cap (lambda x the
    scenario's stride is longer) and its swing feet rise to the YAML's clearance, not lambda x the
    scenario's."""
    text = (resources.files("gaitshift.robots") / "configs" / "op3.yaml").read_text()
    runs = {}
    for tag, body in (("plain", text.split("\ngait:")[0]), ("shipped", text)):
        path = tmp_path / f"op3-{tag}.yaml"
        path.write_text(body.replace("name: op3", f"name: op3-{tag}"))
        sc = scale_scenario("g1-walk-run-walk", str(path))
        runs[tag] = (sc, gaitshift.plan(sc))
    for sc, traj in runs.values():
        lift = np.max(traj.foot_pos[:, :, 2]) - np.min(traj.foot_pos[:, :, 2])
        assert np.isclose(lift, sc.swing_height, rtol=0.02)
    (plain, plain_traj), (shipped, shipped_traj) = runs["plain"], runs["shipped"]
    assert np.max(np.diff(plain_traj.footsteps[:, 0])) > 0.1 and plain.swing_height > 0.015
    assert np.isclose(np.max(np.diff(shipped_traj.footsteps[:, 0])), 0.04) and np.isclose(shipped.swing_height, 0.01)
