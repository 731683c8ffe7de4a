"""A humanoid gaitshift has never seen, built from scratch in the test (an MJCF of boxes and capsules
whose masses come from its geoms, and a robot YAML of eight lines), walks closed loop on its own
estimator: ``robot check`` finds no problem, the G1's walk scaled to it finishes every step without a
fall, and the estimate meets the G1's bar (contact >= 95 %, base velocity <= 0.05 m/s, tilt <= 0.01
rad RMS). The run, the walk-run-walk and the tour pass too (docs/robots.md, "A robot from scratch")."""

from __future__ import annotations

import json

LEG = """
      <body name="{s}_thigh" pos="0 {y} -0.06">
        <joint name="{s}_hip_yaw" axis="0 0 1" range="-0.6 0.6"/>
        <joint name="{s}_hip_roll" axis="1 0 0" range="-0.5 0.5"/>
        <joint name="{s}_hip_pitch" axis="0 1 0" range="-1.8 0.8"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.38" size="0.05" mass="4"/>
        <body name="{s}_shin" pos="0 0 -0.38">
          <joint name="{s}_knee" axis="0 1 0" range="0 2.4"/>
          <geom type="capsule" fromto="0 0 0 0 0 -0.38" size="0.04" mass="2.5"/>
          <body name="{s}_foot" pos="0 0 -0.38">
            <joint name="{s}_ankle_pitch" axis="0 1 0" range="-0.9 0.6"/>
            <joint name="{s}_ankle_roll" axis="1 0 0" range="-0.4 0.4"/>
            <geom type="box" pos="0.03 0 -0.04" size="0.11 0.05 0.015" mass="1" contype="1" conaffinity="1"/>
          </body>
        </body>
      </body>"""
#: torque limits, N m
LIMITS = {"hip_yaw": 80, "hip_roll": 120, "hip_pitch": 150, "knee": 200, "ankle_pitch": 80, "ankle_roll": 50}
MOTORS = "".join(f'\n    <motor joint="{s}_{j}" ctrlrange="-{t} {t}"/>' for s in ("l", "r") for j, t in LIMITS.items())
MJCF = f"""<mujoco model="scratch">
  <compiler angle="radian"/>
  <default>
    <joint armature="0.02" damping="0.1" frictionloss="0.1" limited="true"/>
    <geom contype="0" conaffinity="0"/>
    <motor ctrllimited="true"/>
  </default>
  <worldbody>
    <body name="pelvis" pos="0 0 0.9">
      <freejoint name="root"/>
      <geom type="box" size="0.08 0.14 0.06" mass="8"/>
      <body name="torso" pos="0 0 0.3"><geom type="box" size="0.1 0.16 0.22" mass="14"/></body>
      {LEG.format(s="l", y=0.1)}{LEG.format(s="r", y=-0.1)}
    </body>
  </worldbody>
  <actuator>{MOTORS}
  </actuator>
</mujoco>
"""
#: the whole robot YAML: everything else is read from the model
ROBOT = """name: scratch
mjcf: scratch.xml
soles: {left: {body: l_foot}, right: {body: r_foot}}
torso: torso
hips: [l_hip_pitch, r_hip_pitch]
knees: [l_knee, r_knee]
leg_joints: [l_hip_yaw, l_hip_roll, l_hip_pitch, l_knee, l_ankle_pitch, l_ankle_roll,
             r_hip_yaw, r_hip_roll, r_hip_pitch, r_knee, r_ankle_pitch, r_ankle_roll]
"""


def test_a_humanoid_built_from_scratch_walks_on_its_estimator(cli, tmp_path):
    (tmp_path / "scratch.xml").write_text(MJCF)
    robot = tmp_path / "scratch.yaml"
    robot.write_text(ROBOT)
    code, out, err = cli(["robot", "check", str(robot)])
    assert code == 0 and out.strip().endswith("scratch: 0 problems"), out + err
    walk = tmp_path / "walk.yaml"
    assert cli(["scale", "g1-walk", "--robot", str(robot), "--out", str(walk)])[0] == 0
    code, out, err = cli(["simulate", str(walk), "--out", str(tmp_path / "walk.npz"), "--json"])
    m = json.loads(out)
    assert code == 0 and not m["fell"], err
    assert m["steps_completed"] == m["steps_planned"] == 11
    assert m["state_source"] == "estimated"
    est = m["estimation"]
    assert est["contact_accuracy"] >= 0.95 and est["base_vel_rmse"] <= 0.05 and est["tilt_rmse"] <= 0.01
