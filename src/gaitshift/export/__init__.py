"""Reference motions for the tools users already live in: whole-body motion files for RL trackers.

Modules: :mod:`source` (the motion to export: a plan through the whole-body IK, or a simulation log),
:mod:`resample` (frames at a new rate: lerp, slerp, continuous quaternions), :mod:`kinematics` (MuJoCo
forward kinematics of every body, joint and body order), :mod:`formats` (the ``FORMATS`` registry:
``unitree-csv``, ``mjlab-npz``) and :mod:`motion` (``export_motion``: source -> frames -> file).

Public API::

    from gaitshift.export.motion import export_motion
    report = export_motion("plan.npz", "walk.npz", "mjlab-npz", robot="g1")   # fps 50 by default

It imports mujoco and mink (the ``robot`` extra). docs/export.md documents the formats and the joint
and body order of every built-in robot.
"""
