"""``gaitshift robot check``: one line per check, exit 1 with a PROBLEM line for each thing that will
fail (a tilted sole frame, soles whose contact points span no area, a joint speed above its limit),
exit 0 for a robot that is fine; a sole frame the legs cannot turn flat, or a zero quaternion, is one
error line naming ``sole_orientation`` (exit 2)."""

from __future__ import annotations

from importlib import resources

from gaitshift.wholebody.scaling import scale_scenario, scenario_yaml


def _yaml(name: str) -> str:
    return (resources.files("gaitshift.robots") / "configs" / f"{name}.yaml").read_text()


def test_a_shipped_robot_passes_the_standing_checks(cli):
    code, out, _ = cli(["robot", "check", "g1"])
    assert code == 0 and "PROBLEM" not in out
    assert {"sole frame", "balance", "static torque"} <= {line[8:].split(":")[0] for line in out.splitlines()[:-1]}


def test_a_tilted_sole_frame_is_one_problem_line_per_sole(cli, tmp_path):
    path = tmp_path / "b.yaml"
    path.write_text(
        _yaml("berkeley").replace(
            "\nsole_orientation: geoms", "\nsole_orientation: body\nstanding_pose: {LL_KFE: 0.5, LR_KFE: 0.5}"
        )
    )
    code, out, _ = cli(["robot", "check", str(path)])
    problems = [line for line in out.splitlines() if line.startswith("PROBLEM")]
    assert code == 1
    assert sum("sole frame" in p for p in problems) == 2 and all("sole_orientation" in p for p in problems[:2])


def test_a_joint_speed_limit_below_the_plans_peak_is_named(cli, tmp_path):
    """The knee's limit is set to half the peak speed that the check itself measures with a loose limit."""
    robot = tmp_path / "t1.yaml"
    robot.write_text(_yaml("t1") + "velocity_limits: {Left_Knee_Pitch: 1000.0}\n")
    scenario = tmp_path / "walk.yaml"
    scenario.write_text(scenario_yaml(scale_scenario("g1-walk", str(robot))))
    code, out, _ = cli(["robot", "check", str(robot), str(scenario)])
    assert code == 0, out
    line = next(x for x in out.splitlines() if x.startswith("ok      joint speed: peak"))
    peak = float(line.split("Left_Knee_Pitch: ")[1].split(" of")[0])
    robot.write_text(_yaml("t1") + f"velocity_limits: {{Left_Knee_Pitch: {peak / 2:.3f}}}\n")
    code, out, _ = cli(["robot", "check", str(robot), str(scenario)])
    problems = [x for x in out.splitlines() if x.startswith("PROBLEM")]
    assert code == 1 and len(problems) == 1
    assert "Left_Knee_Pitch needs" in problems[0] and f"{peak / 2:.2f} rad/s" in problems[0]


def test_op3_servos_are_too_slow_for_the_g1_walk_scaled_down(cli, tmp_path):
    """OP3's MJCF damping (1.084 N m s/rad) eats its 5 N m at 4.61 rad/s: the G1's walk scaled down
    (op3.yaml without its ``gait`` choices, Froude timing) needs more, and the problem lines name the MJCF
    as the source of that bound; with the shipped ``gait`` choices the same scaling passes the check."""
    robot = tmp_path / "op3-plain.yaml"
    robot.write_text(_yaml("op3").split("\ngait:")[0].replace("name: op3", "name: op3-plain"))
    scenario = tmp_path / "walk.yaml"
    scenario.write_text(scenario_yaml(scale_scenario("g1-walk", str(robot), time_scale="froude")))
    code, out, _ = cli(["robot", "check", str(robot), str(scenario)])
    problems = [x for x in out.splitlines() if x.startswith("PROBLEM")]
    assert code == 1 and problems
    assert all("joint speed" in p and "above its limit 4.61 rad/s (torque limit / joint damping" in p for p in problems)
    scenario.write_text(scenario_yaml(scale_scenario("g1-walk", "op3")))
    code, out, _ = cli(["robot", "check", "op3", str(scenario)])
    assert code == 0 and "PROBLEM" not in out, out


def test_robot_errors_are_one_line_with_exit_2(cli, tmp_path):
    """Unknown name: the valid names; missing file: "no such file"; missing key: that key alone."""
    code, _, err = cli(["robot", "check", "nao"])
    assert code == 2 and err.count("\n") == 1 and "berkeley, g1, h1, op3, t1" in err and "no such file" not in err
    code, _, err = cli(["robot", "check", str(tmp_path / "mine.yaml")])
    assert code == 2 and err.count("\n") == 1 and "no such file" in err
    bad = tmp_path / "bad.yaml"
    bad.write_text("\n".join(line for line in _yaml("t1").splitlines() if not line.startswith("knees:")))
    code, _, err = cli(["robot", "check", str(bad)])
    assert (
        code == 2
        and err.strip() == "gaitshift: error: robot.knees = missing is invalid: allowed a value (required key)"
    )


APOLLO = "asset:mujoco/playground/assets/mujoco_menagerie/apptronik_apollo/apptronik_apollo.xml"


def test_soles_on_a_line_are_a_balance_problem_not_a_crash(cli, tmp_path):
    """Apollo without ``sole_orientation``: each foot's lowest points are one edge (2 points per sole, on
    a line in the ground plane); that used to end in scipy's QhullError traceback."""
    path = tmp_path / "apollo.yaml"
    path.write_text(
        f"name: apollo\nmjcf: {APOLLO}\nsoles: {{left: {{body: l_foot_link}}, right: {{body: r_foot_link}}}}\n"
        "torso: torso_link\nhips: [l_hip_fe, r_hip_fe]\nknees: [l_knee_fe, r_knee_fe]\n"
        "leg_joints: [l_hip_ie, l_hip_aa, l_hip_fe, l_knee_fe, l_ankle_ie, l_ankle_pd,"
        " r_hip_ie, r_hip_aa, r_hip_fe, r_knee_fe, r_ankle_ie, r_ankle_pd]\n"
    )
    code, out, err = cli(["robot", "check", str(path)])
    problems = [x for x in out.splitlines() if x.startswith("PROBLEM")]
    assert code == 1 and err == "", err
    assert any(p.startswith("PROBLEM balance:") and "sole_orientation" in p for p in problems), out


def test_berkeley_without_sole_orientation_names_the_sole_frame(cli, tmp_path):
    """Its computed standing pose cannot make the rotated foot frames flat: the one line names
    ``sole_orientation`` (it used to name ``com_height``)."""
    path = tmp_path / "b.yaml"
    path.write_text(_yaml("berkeley").replace("\nsole_orientation: geoms", ""))
    code, _, err = cli(["robot", "check", str(path)])
    assert code == 2 and err.count("\n") == 1
    assert err.startswith("gaitshift: error: robot.sole_orientation = 'body' is invalid") and "geoms" in err


def test_a_zero_sole_quaternion_is_refused_by_the_schema(cli, tmp_path):
    path = tmp_path / "b.yaml"
    path.write_text(
        _yaml("berkeley").replace(
            "\nsole_orientation: geoms", "\nsole_orientation: {left: [0, 0, 0, 0], right: [1, 0, 0, 0]}"
        )
    )
    code, _, err = cli(["robot", "check", str(path)])
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith("gaitshift: error: robot.sole_orientation = ") and "norm >= 0.1" in err


def test_a_joint_at_its_range_limit_in_the_standing_pose_is_a_problem(cli, tmp_path):
    """The T1's elbow pitch range is [-2.27, 2.27] rad: standing with it at 2.27 is one PROBLEM line naming it."""
    path = tmp_path / "t1.yaml"
    path.write_text(_yaml("t1").replace("standing_pose:\n", "standing_pose:\n  Left_Elbow_Pitch: 2.27\n"))
    code, out, _ = cli(["robot", "check", str(path)])
    problems = [x for x in out.splitlines() if x.startswith("PROBLEM")]
    assert code == 1 and len(problems) == 1, out
    assert problems[0].startswith("PROBLEM standing limits: Left_Elbow_Pitch = 2.270 rad"), problems
