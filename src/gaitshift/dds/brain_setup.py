"""What the brain is built from: the controller of its scenario, the safety machine of its robot, and the
check that a real robot may be taken over (:mod:`gaitshift.dds.brain`)."""

from typing import Any

from gaitshift.control.controller import Controller
from gaitshift.dds.brain_options import BrainOptions
from gaitshift.dds.g1 import check_motor_order
from gaitshift.dds.gravity import standing_torques
from gaitshift.dds.safety import Limits, Safety, SafetySettings, standup_gains

__all__ = ["PASSIVE_TAU", "build_controller", "passive_at_start", "safety_of"]

#: |tau_est| N m under which a motor counts as passive (zero torque) at a real robot's start
PASSIVE_TAU = 1.0


def build_controller(opts: BrainOptions) -> Controller:
    """The controller of ``opts.scenario`` on ``opts.robot`` with ``contact=opts.contact``,
    ``replan=opts.replan``, ``latency=opts.command_latency`` and ``known_floor=opts.known_floor``; its
    motors must be the hg slots in order (the G1)."""
    ctrl = Controller.from_scenario(
        opts.scenario,
        opts.robot,
        known_floor=opts.known_floor,
        contact=opts.contact,
        replan=opts.replan,
        latency=opts.command_latency,
    )
    check_motor_order(ctrl.motor_names)
    return ctrl


def passive_at_start(state: Any, n: int) -> bool:
    """A real robot may be taken over: every motor of slots 0..n-1 reports mode 0 (disabled), or every one
    a torque under :data:`PASSIVE_TAU` N m (zero torque / damping)."""
    motors = state.motor_state[:n]
    return all(m.mode == 0 for m in motors) or all(abs(m.tau_est) < PASSIVE_TAU for m in motors)


def safety_of(ctrl: Controller, opts: BrainOptions) -> Safety:
    """The safety machine of ``ctrl``'s robot: limits from its model and YAML, the start pose's joints."""
    cfg, model = ctrl.robot.robot, ctrl.robot.model
    speed, _ = cfg.speed_limits()
    limits = Limits.of_robot(cfg.joint_names, cfg.joint_range, speed, cfg.torque_limit, ctrl.motor_names)
    kp, kd = standup_gains(limits.tau_max)
    adr = [int(model.joint(name).qposadr[0]) for name in ctrl.motor_names]
    tau = standing_torques(ctrl.robot, ctrl.initial_qpos())
    settings = SafetySettings(
        kp, kd, tau, opts.damping_time, opts.standup_time, opts.damping_kd, opts.stale, opts.tilt, hold_time=opts.hold
    )
    return Safety(limits, settings, ctrl.initial_qpos()[adr])
