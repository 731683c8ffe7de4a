"""Whole-body IK on the Unitree G1, checked through MuJoCo forward kinematics alone.

The checks recompute everything from the joint trajectories (:mod:`mujoco_checks`): the whole-body
CoM as the mass-weighted mean of the body CoMs (``xipos``, ``body_mass``), the sole poses from the
sole body pose and the sole offset of the robot YAML, the joint limits and velocity limits from the
MJCF/URDF numbers, the joint velocities from finite differences and quaternion kinematics. No
gaitshift IK code is used to judge it.
"""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET

import mujoco
import numpy as np
import pytest

import gaitshift
from gaitshift.errors import GaitshiftError, InfeasibleError
from gaitshift.robots import load_robot
from gaitshift.wholebody.ik import wholebody
from gaitshift.wholebody.joints import subsample
from mujoco_checks import angle_diff, robot_fk, tilt, yaw

RATE = 500.0


def fk_check(robot, traj, joints):
    """Worst CoM error (m), sole position error (m), sole tilt (rad) and sole yaw error (rad) over all
    samples, by forward kinematics of a plain MuJoCo model of the robot's MJCF."""
    yaw_of = {}
    for fs, side in zip(traj.footsteps, traj.footstep_side, strict=True):
        yaw_of.setdefault(int(side), set()).add(round(float(fs[3]), 9))
    assert all(len(v) == 1 for v in yaw_of.values()), "these checks assume straight-line plans"
    yaws = np.array([yaw_of[0].pop(), yaw_of[1].pop()])
    com, soles, rot = robot_fk(robot, joints.qpos)
    e_com = np.max(np.linalg.norm(com - traj.com_pos, axis=1))
    e_pos = np.max(np.linalg.norm(soles - traj.foot_pos, axis=2))
    e_yaw = np.max(np.abs(angle_diff(yaw(rot), yaws)))
    return e_com, e_pos, np.max(tilt(rot)), e_yaw


def mjcf_joint_ranges(path):
    """{joint: (lo, hi)} read from the MJCF text."""
    root = ET.parse(path).getroot()
    return {
        j.get("name"): tuple(float(x) for x in j.get("range").split()) for j in root.iter("joint") if j.get("range")
    }


#: (built-in scenario, IK rate): the TV-LIPM plan is sampled at 1 kHz, IK at 500 Hz; the online VHIP
#: plan comes at the paper's 4 ms control period, IK at every sample.
PLANS = {"g1-walk-run-walk": RATE, "g1-online-variable-speed": None}


@pytest.fixture(scope="module", params=list(PLANS))
def g1_plan(request):
    robot = load_robot("g1")
    traj = subsample(gaitshift.plan(gaitshift.load_scenario(request.param)), PLANS[request.param])
    joints = wholebody(traj, robot)
    return robot, traj, joints


def test_ik_reproduces_planned_com_and_soles_on_g1(g1_plan):
    robot, traj, joints = g1_plan
    assert np.any(traj.phase == 2), "the plan must contain flight phases"
    e_com, e_pos, e_tilt, e_yaw = fk_check(robot, traj, joints)
    assert e_com < 2e-3
    assert e_pos < 1e-3
    assert e_tilt < 0.01 and e_yaw < 0.01


def test_g1_plans_respect_joint_limits_of_the_mjcf(g1_plan):
    robot, _, joints = g1_plan
    m = mujoco.MjModel.from_xml_path(str(robot.mjcf))
    ranges = mjcf_joint_ranges(robot.mjcf)
    assert len(ranges) == 29
    for name, (lo, hi) in ranges.items():
        q = joints.qpos[:, m.joint(name).qposadr[0]]
        assert q.min() >= lo - 1e-9 and q.max() <= hi + 1e-9, name


def test_g1_joint_velocities_are_the_derivative_of_q_and_within_limits(g1_plan):
    robot, _, joints = g1_plan
    m = mujoco.MjModel.from_xml_path(str(robot.mjcf))
    dt = float(joints.t[1] - joints.t[0])
    assert np.all(np.isfinite(joints.qvel))
    # hinge joints: qvel is the time derivative of q (second-order differences)
    grad = np.gradient(joints.qpos[:, 7:], dt, axis=0)
    assert np.max(np.abs(grad[1:-1] - joints.qvel[1:-1, 6:])) < 1e-9
    # free joint: world linear velocity, body angular velocity w = 2 Im(conj(quat) dquat/dt)
    assert np.max(np.abs(np.gradient(joints.qpos[:, :3], dt, axis=0)[1:-1] - joints.qvel[1:-1, :3])) < 1e-9
    quat = joints.qpos[:, 3:7]
    dquat = np.gradient(quat, dt, axis=0)
    w, x, y, z = quat.T
    dw, dx, dy, dz = dquat.T
    omega = 2 * np.stack(
        [w * dx - x * dw - y * dz + z * dy, w * dy + x * dz - y * dw - z * dx, w * dz - x * dy + y * dx - z * dw],
        axis=1,
    )
    assert np.max(np.abs(omega[1:-1] - joints.qvel[1:-1, 3:6])) < 1e-3 * max(1.0, np.abs(omega).max())
    # velocity limits of the Unitree URDF (robot YAML), one per joint
    limits = np.array(
        [dict(zip(robot.joint_names, robot.velocity_limit, strict=True))[m.joint(j).name] for j in range(1, m.njnt)]
    )
    assert np.all(np.isfinite(limits))
    assert np.all(np.abs(joints.qvel[:, 6:]) <= limits)


def test_joints_file_holds_mujoco_order_and_metadata(g1_plan, tmp_path):
    robot, _, joints = g1_plan
    path = joints.save(tmp_path / "joints.npz")
    with np.load(path) as z:
        meta = json.loads(str(z["meta"]))
        m = mujoco.MjModel.from_xml_path(meta["mjcf"])
        assert z["qpos"].shape == (len(z["t"]), m.nq) and z["qvel"].shape == (len(z["t"]), m.nv)
    assert meta["joint_names"] == [m.joint(j).name for j in range(1, m.njnt)]
    assert m.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE
    assert meta["mjcf"] == str(robot.mjcf)


def _huge_stride(robot, steps: int) -> dict:
    """A walking scenario for ``robot`` whose stride is twice its leg length (beyond any reach)."""
    return {
        "planner": "tvlip",
        "height": robot.com_height,
        "foot": {"size": list(robot.sole_size), "zmp_margin": 0.005},
        "gait": [{"gait": "walk", "steps": steps}],
        "profile": {
            "max_stride": 2 * robot.leg_length,
            "accelerate_steps": 0,
            "decelerate_steps": 0,
            "step_width": robot.foot_separation,
        },
        "limits": {"max_stride": 3 * robot.leg_length},
    }


def test_stride_of_twice_the_leg_length_names_the_time_and_the_task():
    g1 = load_robot("g1")
    sc = gaitshift.load_scenario(_huge_stride(g1, 4) | {"name": "g1-huge-stride", "swing_height": 0.05})
    traj = gaitshift.plan(sc)
    with pytest.raises(InfeasibleError) as info:
        wholebody(traj, g1, rate=RATE)
    err = info.value
    assert isinstance(err, GaitshiftError)
    assert err.task in ("left sole", "right sole", "com")
    assert f"t = {err.time:.3f} s" in str(err) and f"'{err.task}'" in str(err)
    # the first sample the IK rejects is one where a foot target is beyond the leg's reach of the
    # standing hip, or the knee has straightened: it cannot lie in the standing start
    k = int(np.searchsorted(traj.t, err.time - 1e-9))
    assert not np.all(traj.phase[: k + 1] == 0)
    assert "out of reach" in str(err) or "singularity" in str(err)


def test_cli_wholebody_writes_joints_and_reports_infeasible_plans_in_one_line(tmp_path, capsys):
    import yaml

    from gaitshift.cli import main

    g1 = load_robot("g1")
    bad = tmp_path / "huge.yaml"
    bad.write_text(yaml.safe_dump(_huge_stride(g1, 2)))
    out = tmp_path / "j.npz"
    with pytest.raises(SystemExit) as ex:
        main(["wholebody", str(bad), "--robot", "g1", "--out", str(out), "--rate", "250"])
    assert ex.value.code == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "t = " in err and "sole" in err
    assert not out.exists()


def test_soles_turn_with_the_footsteps_on_a_curved_walk():
    """On a walk turning 0.15 rad per step, each sole in contact has the yaw of the footstep it stands
    on (found by position, from forward kinematics)."""
    g1 = load_robot("g1")
    sc = gaitshift.load_scenario(
        {
            "planner": "tvlip",
            "height": g1.com_height,
            "foot": {"size": list(g1.sole_size), "zmp_margin": 0.005},
            "gait": [{"gait": "walk", "steps": 6}],
            "swing_height": 0.05,
            "profile": {
                "max_stride": 0.2,
                "accelerate_steps": 2,
                "decelerate_steps": 2,
                "step_width": g1.foot_separation,
                "yaw_rate": 0.15,
            },
        }
    )
    traj = subsample(gaitshift.plan(sc), 250)
    joints = wholebody(traj, g1)
    _, soles, rot = robot_fk(g1, joints.qpos)
    worst, checked = 0.0, 0
    for k in range(0, len(joints.t), 5):
        for side in (0, 1):
            if not traj.contact[k, side]:
                continue
            steps = traj.footsteps[traj.footstep_side == side]
            dist = np.linalg.norm(steps[:, :2] - soles[k, side, :2], axis=1)
            assert dist.min() < 1e-3
            worst = max(worst, abs(angle_diff(yaw(rot[k, side]), steps[np.argmin(dist), 3])))
            checked += 1
    assert checked > 100 and np.ptp(traj.footsteps[:, 3]) > 0.5
    assert worst < 0.01
