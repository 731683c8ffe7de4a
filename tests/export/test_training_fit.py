"""Plan exports are fit for training, judged from the files with numpy and a plain MuJoCo model:

* every joint of the G1 plan exports (g1-walk, g1-walk-run-walk) stays within the soft range mjlab
  clips to at reset (the middle 90 % of the MJCF range, mjlab's G1 ``soft_joint_pos_limit_factor``),
  which the IK's default motion of the same plan leaves (so the check can fail);
* the pelvis roll and roll rate of the exports stay within those of the simulated runs: g1-walk's
  against the simulation made by the conftest, g1-walk-run-walk's against its measured run;
* a swing sole may pitch in the air, but is flat on every frame where the plan has it in contact, but
  for the rear sole of a double support, which may lift its heel about its toe (toe-off);
* g1-slope-down, refused before (the rear ankle at its soft limit with both soles flat), exports with
  every joint in the soft range, its CoM on the plan's, its soles in contact on the ramp and its
  toe-offs within the support the plan's ZMP needs; the ground check refuses soles held flat on a ramp
  (what the reference IK did before: a corner 16 mm inside the ramp);
* g1-slope-up, refused before (its rear heel lifted while the plan's ZMP was still on it, 88.6 mm
  outside the toe-off support), lifts a heel only where the plan's ZMP is ahead of that sole's toe edge;
* g1-run-slope-up and g1-stairs-down, refused before (a stance ankle at its soft limit; the knee at
  21.2 rad/s), export every frame within the soft range and every joint speed within its limit;
* g1-run-turn, refused before (the trailing sole out of reach in flight), frees the soles of those
  flight samples only, keeping the CoM to ``com_tol``, the soles within a millimetre of the plan's
  path horizontally (lifted above it) and every sole corner above the floor;
* no foot goes through the ground in the air: the contact spheres of the MJCF's feet stay on or above
  the plan's terrain in every swing of g1-walk-run-walk (12.9 mm below before, the toe of a sole pitched
  down just after lift-off), the sole lifted above the plan's swing path there instead, on the plan's
  path horizontally;
* the mjlab format's rules not checked elsewhere: the exact keys and dtypes, joints in the MJCF's
  order, the base quaternion w first (an upright robot), linear velocities of the body frame origin
  (the velocity of the body's CoM fails the same difference check).
"""

from __future__ import annotations

import functools
from dataclasses import replace

import mujoco
import numpy as np
import pytest

from gaitshift.api import plan as plan_of
from gaitshift.cli import main
from gaitshift.export.motion import export_motion
from gaitshift.models.terrain import Terrain
from gaitshift.robots import load_robot
from gaitshift.scenario.loader import load_scenario
from gaitshift.trajectory.contract import Trajectory
from gaitshift.wholebody.ik import REFERENCE_SETTINGS, IKInfeasibleError, WholeBodyIK
from gaitshift.wholebody.ik_tasks import trailing_soles
from gaitshift.wholebody.joints import subsample
from mujoco_checks import robot_fk

#: mjlab 1.6.0's G1 (asset_zoo/robots/unitree_g1/g1_constants.py): soft_joint_pos_limit_factor = 0.9
MJLAB_SOFT_FACTOR = 0.9
#: the simulated g1-walk-run-walk run (`gaitshift simulate g1-walk-run-walk`, estimated state, did not
#: fall; docs/export.md "Fit for training"): pelvis roll within [-2.0, +1.8] deg, roll rate <= 0.33 rad/s
SIM_WRW_ROLL_DEG, SIM_WRW_ROLL_RATE = 2.0, 0.33
#: bound on the 95th percentile of |v - central difference| at 50 fps, m/s (as tests/export/test_motion_files.py)
P95 = 0.03
MJLAB_KEYS = {"fps", "joint_pos", "joint_vel", "body_pos_w", "body_quat_w", "body_lin_vel_w", "body_ang_vel_w"}


def run(argv: list) -> int:
    """``gaitshift argv`` in-process; its exit code."""
    with pytest.raises(SystemExit) as exc:
        main([str(a) for a in argv])
    return int(exc.value.code or 0)


@functools.cache
def plain_model(robot: str) -> mujoco.MjModel:
    """The robot's MJCF compiled as shipped (no gaitshift additions)."""
    return mujoco.MjModel.from_xml_path(str(load_robot(robot).mjcf))


def linear_difference_error(pos: np.ndarray, vel: np.ndarray, fps: int) -> np.ndarray:
    """|vel - central difference of pos| (F-2, B) at frames 1 .. F-2, m/s."""
    return np.linalg.norm((pos[2:] - pos[:-2]) * fps / 2 - vel[1:-1], axis=-1)


def rotate(quat: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Vectors ``v`` (B, 3) rotated by the unit quaternions ``quat`` (F, B, 4), w x y z: (F, B, 3)."""
    w, u = quat[..., :1], quat[..., 1:]
    t = 2 * np.cross(u, np.broadcast_to(v, u.shape))
    return v + w * t + np.cross(u, t)


@pytest.fixture(scope="module")
def wrw(tmp_path_factory):
    """(plan .npz, its mjlab-npz export) of g1-walk-run-walk, made through the CLI."""
    d = tmp_path_factory.mktemp("wrw")
    plan, out = d / "wrw.npz", d / "wrw-motion.npz"
    assert run(["plan", "g1-walk-run-walk", "--out", plan]) == 0
    assert run(["export", plan, "--format", "mjlab-npz", "--out", out]) == 0
    return plan, out


@functools.cache
def soft_range(robot: str) -> tuple[list[str], np.ndarray]:
    """Joint names (MJCF order) and mjlab's soft range (J, 2) of each, from the plain model."""
    m = plain_model(robot)
    ids = [j for j in range(m.njnt) if m.jnt_type[j] != mujoco.mjtJoint.mjJNT_FREE]
    rng = m.jnt_range[ids]
    mid, half = rng.mean(axis=1), (rng[:, 1] - rng[:, 0]) / 2
    return [m.joint(j).name for j in ids], np.stack([mid - MJLAB_SOFT_FACTOR * half, mid + MJLAB_SOFT_FACTOR * half], 1)


def frames_outside(names: list[str], joint_pos: np.ndarray) -> int:
    """Frames with a joint outside mjlab's soft range (1e-9 rad of rounding allowed)."""
    order, rng = soft_range("g1")
    cols = [order.index(n) for n in names]
    lo, hi = rng[cols, 0], rng[cols, 1]
    return int(np.sum(np.any((joint_pos < lo - 1e-9) | (joint_pos > hi + 1e-9), axis=1)))


def pelvis_roll(z) -> tuple[np.ndarray, np.ndarray]:
    """Pelvis roll (rad, about its forward axis after yaw and pitch) and the angular velocity about its
    own x axis (rad/s) of each frame."""
    w, x, y, zz = np.asarray(z["body_quat_w"][:, 0]).T
    roll = np.arctan2(2 * (w * x + y * zz), 1 - 2 * (x * x + y * y))
    x_axis = np.stack([1 - 2 * (y * y + zz * zz), 2 * (x * y + w * zz), 2 * (x * zz - w * y)], axis=1)
    return roll, np.sum(z["body_ang_vel_w"][:, 0] * x_axis, axis=1)


def test_g1_walk_export_stays_within_the_soft_range_the_default_ik_leaves(exported, motions):
    z = np.load(exported("g1-plan", "mjlab-npz"))
    names = [str(n) for n in z["joint_names"]]
    assert frames_outside(names, z["joint_pos"]) == 0
    joints = WholeBodyIK("g1").solve(Trajectory.load(motions["g1-plan"]), rate=100.0)  # the MJCF range only
    m = plain_model("g1")
    default = joints.qpos[:, [m.jnt_qposadr[m.joint(n).id] for n in names]]
    assert frames_outside(names, default) > 10


def test_g1_walk_run_walk_export_stays_within_the_soft_range(wrw):
    z = np.load(wrw[1])
    assert frames_outside([str(n) for n in z["joint_names"]], z["joint_pos"]) == 0


def test_pelvis_roll_of_the_plan_exports_stays_within_the_simulated_runs(exported, wrw):
    sim_roll, sim_rate = pelvis_roll(np.load(exported("g1-sim", "mjlab-npz")))
    roll, rate = pelvis_roll(np.load(exported("g1-plan", "mjlab-npz")))
    assert sim_roll.min() <= roll.min() and roll.max() <= sim_roll.max()
    assert np.abs(rate).max() <= np.abs(sim_rate).max()
    roll, rate = pelvis_roll(np.load(wrw[1]))
    assert np.degrees(np.abs(roll)).max() <= SIM_WRW_ROLL_DEG
    assert np.abs(rate).max() <= SIM_WRW_ROLL_RATE


def test_swing_soles_pitch_only_in_the_air_and_are_flat_in_contact(wrw):
    plan, z = Trajectory.load(wrw[0]), np.load(wrw[1])
    t = plan.t[0] + np.arange(len(z["joint_pos"])) / 50.0
    k = np.minimum(np.searchsorted(plan.t, t - 1e-9), len(plan.t) - 1)
    contact = plan.contact[k] & plan.contact[np.maximum(k - 1, 0)]  # in contact at and before the frame
    contact &= ~trailing_soles(plan.contact)[k]  # the rear sole of a double support may lift its heel
    bodies = [str(b) for b in z["body_names"]]
    for side, foot in enumerate(("left_ankle_roll_link", "right_ankle_roll_link")):
        _, x, y, _ = z["body_quat_w"][:, bodies.index(foot)].T
        tilt = np.arccos(np.clip(1 - 2 * (x * x + y * y), -1, 1))  # sole normal from the vertical
        assert tilt[contact[:, side]].max() < 0.01
        assert tilt[~contact[:, side]].max() > np.radians(5)  # the freedom is used in the swings


def test_mjlab_npz_has_exactly_its_keys_and_dtypes_and_the_mjcf_joint_order(exported):
    z = np.load(exported("g1-plan", "mjlab-npz"), allow_pickle=False)
    assert set(z.files) == MJLAB_KEYS | {"joint_names", "body_names"}
    assert z["fps"].dtype == np.int64 and z["fps"].tolist() == [50]
    f, j = z["joint_pos"].shape
    b = z["body_pos_w"].shape[1]
    shapes = {"joint_vel": (f, j), "body_quat_w": (f, b, 4), "body_lin_vel_w": (f, b, 3), "body_ang_vel_w": (f, b, 3)}
    for key, shape in shapes.items():
        assert z[key].shape == shape and z[key].dtype == np.float64, key
    assert z["joint_names"].dtype.kind == "U" and z["body_names"].dtype.kind == "U"
    names, _ = soft_range("g1")
    assert [str(n) for n in z["joint_names"]] == names  # every non-free joint, MJCF (qpos) order


def test_the_base_quaternion_is_w_first_the_robot_upright(exported):
    q = np.load(exported("g1-plan", "mjlab-npz"))["body_quat_w"][:, 0]

    def up_z(w, x, y, _z):  # z component of the body z axis
        return 1 - 2 * (x * x + y * y)

    assert up_z(*q.T).min() > np.cos(np.radians(10))  # read as w x y z: upright on every frame
    assert up_z(*np.roll(q, 1, axis=1).T).max() < 0.5  # read as x y z w: upside down


def test_linear_velocities_are_of_the_body_frame_origins(exported):
    z = np.load(exported("g1-plan", "mjlab-npz"))
    pos, vel, w = z["body_pos_w"], z["body_lin_vel_w"], z["body_ang_vel_w"]
    assert np.percentile(linear_difference_error(pos, vel, 50), 95) < P95
    offset = rotate(z["body_quat_w"], plain_model("g1").body_ipos[1:])  # body origin -> body CoM, world
    at_com = vel + np.cross(w, offset)  # the velocity of each body's CoM (mj_objectVelocity's point)
    e = linear_difference_error(pos, at_com, 50)
    assert np.percentile(e, 95) > P95


@pytest.fixture(scope="module")
def slope_down(tmp_path_factory):
    """(plan, export report, mjlab-npz) of g1-slope-down, refused by the reference IK before toe-off."""
    d = tmp_path_factory.mktemp("slope")
    path, out = d / "slope.npz", d / "slope-motion.npz"
    assert run(["plan", "g1-slope-down", "--out", path]) == 0
    report = export_motion(path, out, "mjlab-npz")
    return Trajectory.load(path), report, np.load(out)


def test_g1_slope_down_exports_within_the_soft_range_on_the_plan(slope_down):
    _, report, z = slope_down
    assert frames_outside([str(n) for n in z["joint_names"]], z["joint_pos"]) == 0
    fit = report["ik"]["plan_fit"]
    assert fit["com_error_m"] <= 1e-3 and fit["contact_sole_error_m"] <= 5e-4  # the IK's com_tol, pos_tol
    assert fit["toe_off_samples"] > 0 and fit["zmp_margin_m"] >= 0.0  # the toe-offs it needs, supported
    assert fit["ground_clearance_m"] >= -5e-4
    roll, rate = pelvis_roll(z)
    assert np.degrees(np.abs(roll)).max() <= SIM_WRW_ROLL_DEG and np.abs(rate).max() <= SIM_WRW_ROLL_RATE


def test_g1_slope_down_soles_in_contact_lie_on_the_ramp(slope_down):
    plan, _, z = slope_down
    t = plan.t[0] + np.arange(len(z["joint_pos"])) / 50.0
    k = np.minimum(np.searchsorted(plan.t, t - 1e-9), len(plan.t) - 1)
    bodies = [str(b) for b in z["body_names"]]
    _, x, y, _ = z["body_quat_w"][:, bodies.index("left_ankle_roll_link")].T
    tilt = np.degrees(np.arccos(np.clip(1 - 2 * (x * x + y * y), -1, 1)))
    foot = plan.foot_pos[k, 0]
    on_ramp = plan.contact[k, 0] & ~trailing_soles(plan.contact)[k, 0] & (foot[:, 0] > 0.4) & (foot[:, 0] < 1.6)
    assert on_ramp.sum() > 10
    np.testing.assert_allclose(tilt[on_ramp], 10.0, atol=0.3)  # the 10 deg ramp, not flat


def test_g1_slope_up_lifts_the_rear_heel_only_where_the_plans_zmp_is_off_that_heel():
    traj = subsample(plan_of(load_scenario("g1-slope-up")), 200.0)
    joints = WholeBodyIK("g1", REFERENCE_SETTINGS).solve(traj)
    _, _, rot = robot_fk(load_robot("g1"), joints.qpos)
    p = np.arctan(Terrain.from_list(traj.meta["terrain"]).slope(traj.foot_pos[..., 0]))  # (N, 2) ramp pitch
    ground_normal = np.stack([-np.sin(p), np.zeros_like(p), np.cos(p)], axis=-1)
    tilt = np.arccos(np.clip(np.einsum("nsi,nsi->ns", rot[..., :, 2], ground_normal), -1, 1))
    heel_up = traj.contact.astype(bool) & (tilt > 0.01)  # 10 mrad: the heel 1.8 mm up
    assert heel_up.sum() > 20  # the toe-offs the rear ankle's soft range needs
    k, rear = np.nonzero(heel_up)
    toe_x = traj.foot_pos[k, rear, 0] + 0.09 * np.cos(p[k, rear])  # the rear sole's toe edge
    assert np.all(traj.zmp[k, 0] >= toe_x - 1e-3)  # the plan's ZMP has left the heel: the edge can carry it
    fit = joints.meta["ik"]["plan_fit"]
    assert fit["zmp_margin_m"] >= 0.0 and fit["com_error_m"] <= 1e-3


@pytest.mark.parametrize("name", ["g1-run-slope-up", "g1-stairs-down"])
def test_formerly_refused_g1_plans_export_within_the_soft_range_and_the_speed_limits(tmp_path, name):
    path, out = tmp_path / "plan.npz", tmp_path / "motion.npz"
    assert run(["plan", name, "--out", path]) == 0
    report = export_motion(path, out, "mjlab-npz")
    z = np.load(out)
    names = [str(n) for n in z["joint_names"]]
    assert frames_outside(names, z["joint_pos"]) == 0
    robot = load_robot("g1")
    limit = np.array([robot.velocity_limit[robot.joint_names.index(n)] for n in names])
    assert np.abs(z["joint_vel"]).max(axis=0).max() > 5.0  # the motion is not trivially slow
    assert np.all(np.abs(z["joint_vel"]) <= limit)
    fit = report["ik"]["plan_fit"]
    assert fit["com_error_m"] <= 1e-3 and fit["contact_sole_error_m"] <= 5e-4
    assert fit["ground_clearance_m"] >= -5e-4


def sole_corner_heights(joints, sole_size=(0.18, 0.07)) -> np.ndarray:
    """Height (N, 2) of the lowest corner of each sole, by FK of the plain MJCF (G1 sole sites: the ankle
    roll link's origin moved down to the sole, robots YAML; here the link frame and its sole offset)."""
    robot = load_robot("g1")
    m = plain_model("g1")
    d = mujoco.MjData(m)
    half = np.array([[sx * sole_size[0] / 2, sy * sole_size[1] / 2, 0] for sx in (1, -1) for sy in (1, -1)])
    out = np.empty((len(joints.qpos), 2))
    for k, q in enumerate(joints.qpos):
        d.qpos[:] = q
        mujoco.mj_kinematics(m, d)
        for side in (0, 1):
            body = m.body(robot.sole_bodies[side]).id
            rot = d.xmat[body].reshape(3, 3)
            centre = d.xpos[body] + rot @ np.asarray(robot.sole_offsets[side])
            out[k, side] = (centre + half @ rot.T)[:, 2].min()
    return out


def test_a_flight_out_of_reach_frees_the_soles_but_keeps_the_com_and_the_ground():
    traj = subsample(plan_of(load_scenario("g1-run-turn")), 200.0)
    ik = WholeBodyIK("g1", REFERENCE_SETTINGS)
    joints = ik.solve(traj)
    fit = joints.meta["ik"]["plan_fit"]
    reached = np.array(ik.reached)
    assert len(reached) > 10 and fit["flight_reach_samples"] == len(reached)
    assert np.all(traj.phase[reached] == 2)  # flights only: no sole carries a force
    com, soles, _ = robot_fk(load_robot("g1"), joints.qpos)
    assert np.linalg.norm(com - traj.com_pos, axis=1).max() <= 1e-3  # the CoM stays hard (com_tol)
    assert np.linalg.norm((soles - traj.foot_pos)[reached, :, :2], axis=2).max() < 2e-3  # a millimetre at most
    assert (soles[reached, :, 2] - traj.foot_pos[reached, :, 2]).max() > 5e-4  # the soles lifted to reach
    assert sole_corner_heights(joints)[reached].min() >= -1e-5  # above the floor (33 mm below without the limit)


def test_the_ground_check_refuses_soles_held_flat_on_a_ramp():
    traj = plan_of(load_scenario("g1-run-slope-down"))
    flat = replace(REFERENCE_SETTINGS, terrain_soles=False)
    with pytest.raises(IKInfeasibleError, match=r"task 'ground': a sole corner is 1[56]\.\d mm below the ground"):
        WholeBodyIK("g1", flat).solve(traj, rate=200.0)


def foot_sphere_bottoms(qpos: np.ndarray, terrain: Terrain) -> np.ndarray:
    """Height (N, 2) of the lowest contact sphere of each foot above the terrain under it: MuJoCo FK of the
    plain MJCF, the feet's collision spheres (the G1's four per ankle roll link, r = 5 mm)."""
    m = plain_model("g1")
    d = mujoco.MjData(m)
    feet = [m.body(b).id for b in load_robot("g1").sole_bodies]
    spheres = [
        [g for g in range(m.ngeom) if m.geom_bodyid[g] == b and m.geom_type[g] == mujoco.mjtGeom.mjGEOM_SPHERE]
        for b in feet
    ]
    assert all(len(s) == 4 and (m.geom_contype[s] | m.geom_conaffinity[s]).all() for s in spheres)
    out = np.empty((len(qpos), 2))
    for k, q in enumerate(qpos):
        d.qpos[:] = q
        mujoco.mj_kinematics(m, d)
        for side, s in enumerate(spheres):
            p = d.geom_xpos[s]
            out[k, side] = (p[:, 2] - m.geom_size[s, 0] - terrain.height(p[:, 0])).min()
    return out


def test_no_swing_foot_goes_through_the_ground_its_sole_lifted_instead(wrw):
    traj = subsample(Trajectory.load(wrw[0]), 200.0)
    joints = WholeBodyIK("g1", REFERENCE_SETTINGS).solve(traj)
    air = ~traj.contact.astype(bool)
    clearance = foot_sphere_bottoms(joints.qpos, Terrain.from_list(traj.meta["terrain"]))
    assert clearance[air].min() >= -5e-4  # the IK's pos_tol (12.9 mm below before, t = 3.610 s)
    _, soles, _ = robot_fk(load_robot("g1"), joints.qpos)
    lift = soles[..., 2] - traj.foot_pos[..., 2]
    assert lift[air].max() > 0.005 and lift[air].min() >= -5e-4  # raised where the toe needs it, never lower
    assert np.linalg.norm((soles - traj.foot_pos)[..., :2], axis=2)[air].max() <= 5e-4  # on the path in x, y
    fit = joints.meta["ik"]["plan_fit"]
    assert fit["swing_clearance_m"] >= -5e-4 and fit["swing_lift_m"] == pytest.approx(lift[air].max())
