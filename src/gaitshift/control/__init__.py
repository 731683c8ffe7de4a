"""The robot's brain: from a plan and the measured state to joint torques, every control tick.

Modules: :mod:`wbc` (whole-body inverse-dynamics QP), :mod:`schedule` (foot stance/swing state
machine and force caps), :mod:`feedback` (capture-point step feedback and plan shift),
:mod:`reference` (the tick reference from plan + schedule + feedback), :mod:`plan_samples` (per-sample
quantities derived from the plan), :mod:`online_driver` (re-planning the online VHIP generator from
the measured CoM), :mod:`plant_view` (what the controller needs to know about the robot model).
"""
