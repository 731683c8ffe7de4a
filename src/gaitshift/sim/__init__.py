"""Closed-loop MuJoCo simulation of the Unitree G1 executing gaitshift plans (the world; the robot's
brain is :mod:`gaitshift.control`).

Modules: :mod:`plant` (model with torque motors, from the robot config), :mod:`initial_pose` (standing
on the first footholds), :mod:`contacts` (foot contacts, ground reaction forces, fall test),
:mod:`pushes` (external pushes), :mod:`loop` (``SimOptions`` and ``simulate``: the orchestration),
:mod:`log` (per-tick arrays), :mod:`result` (``SimResult`` and its file), :mod:`metrics` (summary
table), :mod:`video` (MP4 and viewer). Importing this package requires the ``robot`` extra (mujoco,
qpsolvers, daqp).
"""
