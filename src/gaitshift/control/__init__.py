"""The robot's brain: a :class:`~gaitshift.control.controller.Controller` that any world ticks,
a :class:`~gaitshift.control.frames.SensorFrame` in, a :class:`~gaitshift.control.frames.MotorCommand` out.

Modules: :mod:`controller` (the brain, built once and ticked), :mod:`frames` (what crosses the truth
barrier), :mod:`settings` (its configuration), :mod:`state` (estimate or oracle, latency prediction,
friction belief, its own ``MjData``), :mod:`initial_pose` (the pose the plan starts in), :mod:`wbc`
(whole-body inverse-dynamics QP), :mod:`schedule` (foot stance/swing state machine and force caps),
:mod:`feedback` (capture-point step feedback and plan shift), :mod:`reference` (the tick reference from
plan + schedule + feedback), :mod:`plan_samples` (per-sample quantities derived from the plan),
:mod:`drivers` (re-planning streaming plans from the measured CoM), :mod:`replanner` (in the tick or in a
background worker), ``estimation/`` (the state
estimator). The robot model it holds is :class:`gaitshift.robots.model.RobotModel`.
"""
