"""Whole body: scenario scaling to a robot, whole-body IK (mink), joint trajectories and offscreen video.

Modules: :mod:`scaling` (scenarios scaled to a robot), :mod:`ik` (whole-body IK), :mod:`joints`
(``JointTrajectory``, its file, manifold differences, plan loading and subsampling), :mod:`render`
(MP4 of joint trajectories with the plan drawn on top).

Public API::

    from gaitshift.wholebody.scaling import scale_scenario
    from gaitshift.wholebody.ik import wholebody
    sc = scale_scenario("paper001-table2-walk-run-walk", "g1")
    joints = wholebody(gaitshift.plan(sc), "g1", rate=500)   # JointTrajectory: t, qpos, qvel, meta

The IK and the renderer import mujoco and mink (the ``robot`` extra).
"""
