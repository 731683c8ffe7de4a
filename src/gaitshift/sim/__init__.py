"""Closed-loop MuJoCo simulation of the Unitree G1 executing gaitshift plans.

Modules: :mod:`plant` (model with torque motors), :mod:`controller` (whole-body inverse-dynamics QP),
:mod:`loop` (closed loop, foot scheduling, capture-point step feedback, logging), :mod:`metrics`
(summary table). Importing this package requires the ``robot`` extra (mujoco, qpsolvers, daqp).
"""
