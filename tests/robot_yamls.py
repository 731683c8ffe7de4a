"""Robot YAMLs the tests write to files: robots gaitshift does not ship."""

#: Apptronik Apollo from the installed assets (docs/robots.md, "Add your robot")
APOLLO = """name: apollo
mjcf: asset:mujoco/playground/assets/mujoco_menagerie/apptronik_apollo/apptronik_apollo.xml
soles: {left: {body: l_foot_link}, right: {body: r_foot_link}}
sole_orientation: geoms
torso: torso_link
hips: [l_hip_fe, r_hip_fe]
knees: [l_knee_fe, r_knee_fe]
leg_joints: [l_hip_ie, l_hip_aa, l_hip_fe, l_knee_fe, l_ankle_ie, l_ankle_pd,
             r_hip_ie, r_hip_aa, r_hip_fe, r_knee_fe, r_ankle_ie, r_ankle_pd]
"""
