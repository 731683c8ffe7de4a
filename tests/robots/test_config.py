"""Robot configs and scenario scaling, checked against the MJCF text and closed forms; robot YAML
mistakes end in one InputError naming the dotted field (or the file and why it cannot be used)."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from importlib import resources

import mujoco
import numpy as np
import pytest

import gaitshift
from gaitshift.errors import InputError
from gaitshift.robots import builtin_robots, load_robot
from gaitshift.wholebody.scaling import (
    scale_factor,
    scale_scenario,
)


def _mjcf_joints(path):
    root = ET.parse(path).getroot()
    return {j.get("name"): j for j in root.iter("joint") if j.get("name") and j.get("range")}


def test_builtin_robots_are_g1_and_t1():
    assert {"g1", "t1"} <= set(builtin_robots())


def test_g1_limits_and_mass_are_read_from_the_mjcf():
    g1 = load_robot("g1")
    joints = _mjcf_joints(g1.mjcf)
    assert len(g1.joint_names) == 29 and set(g1.joint_names) == set(joints)
    for name, rng, tau in zip(g1.joint_names, g1.joint_range, g1.torque_limit, strict=True):
        lo, hi = (float(x) for x in joints[name].get("range").split())
        assert rng.tolist() == [lo, hi]
        assert tau == max(abs(float(x)) for x in joints[name].get("actuatorfrcrange").split())
    masses = [float(b.get("mass")) for b in ET.parse(g1.mjcf).getroot().iter("inertial")]
    assert g1.mass == pytest.approx(sum(masses), rel=1e-9)
    assert g1.mass == pytest.approx(33.3, abs=0.5)  # the Unitree G1 is 33 kg
    assert len(g1.leg_joints) == 12


def test_nominal_com_height_and_leg_length_follow_from_forward_kinematics():
    for name in ("g1", "t1"):
        r = load_robot(name)
        m = mujoco.MjModel.from_xml_path(str(r.mjcf))
        d = mujoco.MjData(m)
        # standing pose: CoM = sum m_i x_i / M, soles = body pose + YAML offset
        d.qpos[:] = m.qpos0
        d.qpos[:7] = (0, 0, 0, 1, 0, 0, 0)
        for joint, angle in r.standing_pose:
            d.qpos[m.joint(joint).qposadr[0]] = angle
        mujoco.mj_kinematics(m, d)
        com = (m.body_mass[1:, None] * d.xipos[1:]).sum(0) / m.body_mass[1:].sum()
        soles = [
            d.xpos[m.body(b).id] + d.xmat[m.body(b).id].reshape(3, 3) @ np.array(o)
            for b, o in zip(r.sole_bodies, r.sole_offsets, strict=True)
        ]
        assert r.com_height == pytest.approx(com[2] - (soles[0][2] + soles[1][2]) / 2, abs=1e-9)
        assert r.foot_separation == pytest.approx(abs(soles[0][1] - soles[1][1]), abs=1e-9)
        # knees bent: the standing CoM height is below the straight-leg reach
        assert r.com_height < r.leg_length + 0.05
        # leg length: hip-pitch axis to sole with every joint at zero (straight leg)
        d.qpos[7:] = 0.0
        mujoco.mj_kinematics(m, d)
        for side in (0, 1):
            hip = d.xanchor[m.joint(r.hips[side]).id]
            b = m.body(r.sole_bodies[side]).id
            sole = d.xpos[b] + d.xmat[b].reshape(3, 3) @ np.array(r.sole_offsets[side])
            assert np.linalg.norm(hip - sole) >= r.leg_length - 1e-9


def test_g1_sole_is_the_hull_of_its_contact_spheres():
    g1 = load_robot("g1")
    root = ET.parse(g1.mjcf).getroot()
    body = next(b for b in root.iter("body") if b.get("name") == g1.sole_bodies[0])
    pts = np.array([[float(x) for x in g.get("pos").split()] for g in body.findall("geom") if g.get("class") == "foot"])
    r = 0.005  # the foot class sphere radius
    assert len(pts) == 4
    assert g1.sole_offsets[0][2] == pytest.approx(pts[:, 2].min() - r)
    assert g1.sole_offsets[0][0] == pytest.approx((pts[:, 0].min() + pts[:, 0].max()) / 2)
    assert g1.sole_size[0] == pytest.approx(np.ptp(pts[:, 0]) + 2 * r)
    assert g1.sole_size[1] == pytest.approx(np.ptp(pts[:, 1]) + 2 * r)


def test_scaling_multiplies_lengths_by_lambda_and_keeps_timing():
    paper = gaitshift.load_scenario("paper001-table2-walk-run-walk")
    g1 = load_robot("g1")
    sc = scale_scenario(paper, g1)
    lam = g1.com_height / paper.height
    assert scale_factor(paper, g1) == pytest.approx(lam)
    assert sc.height == pytest.approx(g1.com_height)
    assert sc.profile.max_stride == pytest.approx(lam * paper.profile.max_stride)
    assert sc.swing_height == pytest.approx(lam * paper.swing_height)
    assert sc.limits.max_stride == pytest.approx(lam * paper.limits.max_stride)
    assert sc.timing == paper.timing and sc.gait == paper.gait
    assert tuple(sc.foot.size) == g1.sole_size
    assert sc.profile.step_width == pytest.approx(g1.foot_separation)
    # stiffness follows from the new height: walking T_w = sqrt(h/g) (paper 001 §III-A)
    traj = gaitshift.plan(sc)
    assert traj.meta["stiffness"]["T_w"] == pytest.approx(math.sqrt(g1.com_height / 9.81), rel=1e-9)
    # the footholds are the paper's, times lambda, along x
    ref = gaitshift.plan(paper)
    assert np.allclose(traj.footsteps[:, 0], lam * ref.footsteps[:, 0], atol=1e-9)


def test_builtin_g1_walk_run_walk_is_the_scaled_paper_scenario():
    built = gaitshift.load_scenario("g1-walk-run-walk")
    fresh = scale_scenario("paper001-table2-walk-run-walk", "g1", name="g1-walk-run-walk")
    a, b = built.model_dump(), fresh.model_dump()
    a.pop("description"), b.pop("description")
    flat_a, flat_b = _flatten(a), _flatten(b)
    assert flat_a.keys() == flat_b.keys()
    for k in flat_a:
        if isinstance(flat_a[k], float):
            assert flat_a[k] == pytest.approx(flat_b[k], rel=1e-5, abs=1e-9), k
        else:
            assert flat_a[k] == flat_b[k], k


def _flatten(d, prefix=""):
    out = {}
    items = d.items() if isinstance(d, dict) else enumerate(d)
    for k, v in items:
        key = f"{prefix}.{k}" if prefix else str(k)
        if isinstance(v, (dict, list, tuple)):
            out.update(_flatten(v, key))
        else:
            out[key] = v
    return out


def test_bad_robot_yaml_names_the_field(tmp_path):
    text = (resources.files("gaitshift.robots") / "configs" / "g1.yaml").read_text()
    bad = tmp_path / "bad.yaml"
    bad.write_text(text.replace("torso: torso_link", "torso: no_such_body"))
    with pytest.raises(InputError, match=r"robot\.torso"):
        load_robot(bad)
    bad.write_text(text.replace("left_knee_joint: 1.0", "left_knee_joint: 9.0"))
    with pytest.raises(InputError, match=r"standing_pose\.left_knee_joint"):
        load_robot(bad)
    with pytest.raises(InputError, match="robot"):
        load_robot("no-such-robot")


def test_second_robot_runs_the_pipeline_from_its_yaml_alone(tmp_path):
    """The Booster T1 from a YAML copied outside the package: scale, plan, IK, check by FK."""
    from gaitshift.wholebody.ik import subsample, wholebody

    src = (resources.files("gaitshift.robots") / "configs" / "t1.yaml").read_text()
    path = tmp_path / "my_t1.yaml"
    path.write_text(src.replace("name: t1", "name: my-t1"))
    t1 = load_robot(path)
    assert t1.name == "my-t1" and len(t1.joint_names) == 23
    traj = subsample(gaitshift.plan(scale_scenario("paper001-table2-walk-run-walk", t1)), 250)
    joints = wholebody(traj, t1)
    m = mujoco.MjModel.from_xml_path(str(t1.mjcf))
    d = mujoco.MjData(m)
    mass = m.body_mass[1:]
    lo, hi = m.jnt_range[1:].T
    worst_com = worst_sole = 0.0
    for k in range(len(joints.t)):
        d.qpos[:] = joints.qpos[k]
        mujoco.mj_kinematics(m, d)
        com = (mass[:, None] * d.xipos[1:]).sum(0) / mass.sum()
        worst_com = max(worst_com, float(np.linalg.norm(com - traj.com_pos[k])))
        for side in (0, 1):
            b = m.body(t1.sole_bodies[side]).id
            sole = d.xpos[b] + d.xmat[b].reshape(3, 3) @ np.array(t1.sole_offsets[side])
            worst_sole = max(worst_sole, float(np.linalg.norm(sole - traj.foot_pos[k, side])))
    assert worst_com < 2e-3 and worst_sole < 1e-3
    q = joints.qpos[:, 7:]
    assert np.all(q >= lo - 1e-9) and np.all(q <= hi + 1e-9)
    assert np.all(np.isfinite(joints.qvel))


def test_scale_command_writes_a_loadable_scenario_at_the_robots_com_height(tmp_path, capsys):
    import pytest as _pytest

    from gaitshift.cli import main
    from gaitshift.robots import load_robot
    from gaitshift.scenario import load_scenario

    out = tmp_path / "t1.yaml"
    with _pytest.raises(SystemExit) as exc:
        main(["scale", "paper001-table2-walk-run-walk", "--robot", "t1", "--out", str(out)])
    assert exc.value.code == 0
    sc = load_scenario(out)
    t1 = load_robot("t1")
    assert sc.height == _pytest.approx(t1.com_height)
    lam = t1.com_height / 0.95
    assert sc.profile.max_stride == _pytest.approx(0.5 * lam)
    with _pytest.raises(SystemExit) as exc:
        main(["scale", "paper001-table2-walk-run-walk", "--robot", "t1", "--out", str(tmp_path / "x.txt")])
    assert exc.value.code == 2 and not (tmp_path / "x.txt").exists()


# ---------------------------------------------------------------------- robot YAML errors
def _robot_error(arg) -> InputError:
    with pytest.raises(InputError) as exc:
        load_robot(arg)
    assert "\n" not in str(exc.value)
    return exc.value


def _g1_text() -> str:
    return (resources.files("gaitshift.robots") / "configs" / "g1.yaml").read_text()


def test_unknown_robot_lists_the_builtin_names_and_a_missing_file_says_so(tmp_path):
    err = _robot_error("no-such-robot")
    assert err.field == "robot" and "g1, h1, op3, t1" in err.allowed and "no such file" not in err.allowed
    err = _robot_error(tmp_path / "none.yaml")
    assert "no such file" in err.allowed
    (tmp_path / "d.yaml").mkdir()
    assert "folder" in _robot_error(tmp_path / "d.yaml").allowed


def test_a_missing_key_is_named_alone(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("\n".join(line for line in _g1_text().splitlines() if not line.startswith("torso:")))
    err = _robot_error(bad)
    assert str(err) == "robot.torso = missing is invalid: allowed a value (required key)"


@pytest.mark.parametrize(
    "old, new, field",
    [
        ("left_knee_joint: 1.0", "left_knee_joint: .nan", "robot.standing_pose.left_knee_joint"),
        ("left_knee_joint: 1.0", "left_knee_joint: yes", "robot.standing_pose.left_knee_joint"),
        ("sole_size: [0.18, 0.07]", "sole_size: [0.18, -0.07]", "robot.sole_size.1"),
        ("torso: torso_link", "torso: [1, 2]", "robot.torso"),
    ],
)
def test_a_bad_value_names_the_dotted_field(tmp_path, old, new, field):
    bad = tmp_path / "bad.yaml"
    assert old in _g1_text()
    bad.write_text(_g1_text().replace(old, new))
    assert _robot_error(bad).field == field


def test_unreadable_robot_files_and_models_are_named(tmp_path):
    bad = tmp_path / "bad.yaml"
    for raw in (b"\xff\xfe", b"- 1\n", b"a: [\n"):
        bad.write_bytes(raw)
        assert _robot_error(bad).field == "robot"
    text = _g1_text()
    mjcf = next(line for line in text.splitlines() if line.startswith("mjcf:"))
    bad.write_text(text.replace(mjcf, "mjcf: /etc/hostname"))
    assert "ending in .xml" in _robot_error(bad).allowed
    garbage = tmp_path / "g.xml"
    garbage.write_text("<mujoco><worldbody><body name='x'></worldbody>")
    bad.write_text(text.replace(mjcf, f"mjcf: {garbage}"))
    err = _robot_error(bad)
    assert err.field == "robot.mjcf" and "a valid MJCF" in err.allowed
