"""The brain over DDS: :class:`gaitshift.Controller` fed from ``rt/lowstate``, writing ``rt/lowcmd``, behind
the safety state machine (:mod:`gaitshift.dds.safety`).

Each tick::

    take rt/lowstate                  the newest state with a good CRC (bad CRCs dropped and counted), as bytes
    frame_from_lowstate(...)          a NaN or out-of-range field: a fault
    safety.step(t, frame, age)        damping -> stand-up -> locomotion -> stop, or a fault: damping
    ctrl.tick(frame)                  locomotion only; its clock starts when the stand-up ends
    safety.guard(cmd, frame)          q, dq, torque clamped to the robot's limits
    lowcmd_bytes(cmd, mm)             mode 1 on every motor, mode_machine from the state, the CRC set
    write rt/lowcmd

The states are read and the commands written as their CDR bytes (:mod:`gaitshift.dds.cdr`: the same
bytes as cyclonedds's (de)serialization, in a tenth of its time).

Pacing: real time by default (tick ``k`` due at ``t0 + k period`` on the wall clock, the machine's and the
controller's clock the wall clock; a tick that ends over a period after it was due is a missed deadline,
and the ticks it overran are skipped); with ``lockstep`` one tick per new state (``LowState_.tick``
changed), the clocks counting periods, and a state is stale when none came within ``stale`` s of the last
command. A tick's duration runs from the wake-up (real time: the take and deserialization of the states
included) or from the new state's arrival (lockstep) to the command written. The run ends
``final_damping`` s of the machine's clock after it entered ``stop`` or ``fault``. A state's age is the time
since a state of a new tick was last taken (the robot's clock is not compared with the brain's).
Exit codes (:attr:`BrainSummary.exit_code`): 0 the plan ended (or SIGINT/SIGTERM) and the robot damps; 1 a
fault, no state within ``state_timeout`` s, or a real robot that is not damping at start.
"""

import math
import time
from dataclasses import asdict, dataclass, replace
from typing import Any

import numpy as np

from gaitshift.control.controller import Controller
from gaitshift.control.frames import MotorCommand, SensorFrame
from gaitshift.control.replanner import REPLAN_MODES
from gaitshift.dds.cdr import StateBytes
from gaitshift.dds.convert import frame_from_lowstate, lowcmd_bytes
from gaitshift.dds.g1 import check_motor_order
from gaitshift.dds.gravity import standing_torques
from gaitshift.dds.messages import LowState_
from gaitshift.dds.safety import Limits, Safety, SafetySettings, check_settings, standup_gains
from gaitshift.dds.signals import StopSignals
from gaitshift.dds.ticklog import TickLog
from gaitshift.dds.transport import Endpoint, check_domain, open_endpoint
from gaitshift.errors import GaitshiftError, InputError, number_in

__all__ = ["BrainOptions", "BrainSummary", "build_controller", "passive_at_start", "run_brain"]

#: |tau_est| N m under which a motor counts as passive (zero torque) at a real robot's start
PASSIVE_TAU = 1.0


@dataclass(frozen=True)
class BrainOptions:
    """Options of ``gaitshift dds control`` (module docstring; the safety ones: :class:`SafetySettings`).

    Attributes:
        scenario: built-in name or YAML. robot: robot name or YAML (None: the scenario's).
        domain: DDS domain id (0: a real robot, only with ``real_robot``). iface: network interface.
        lockstep: one tick per new state. state_timeout: s to wait for the first state.
        real_robot: allow domain 0; refuse unless the robot is passive at start (:func:`passive_at_start`).
        stale: s. damping_time, standup_time: s. damping_kd: N m s/rad. tilt: rad.
        final_damping: s of damping written after ``stop`` or ``fault`` before exiting.
        contact: the controller's contact detection ("torque": no foot force needed).
        replan: where the controller re-plans (:mod:`gaitshift.control.replanner`; "process": off the tick).
    """

    scenario: str
    robot: str | None = None
    domain: int = 1
    iface: str = "lo"
    lockstep: bool = False
    state_timeout: float = 10.0
    real_robot: bool = False
    stale: float = 0.02
    damping_time: float = 0.1
    standup_time: float = 2.0
    damping_kd: float = 2.0
    tilt: float = 0.6
    final_damping: float = 0.2
    contact: str = "torque"
    replan: str = "process"

    def __post_init__(self) -> None:
        check_domain(self.domain)
        if self.domain == 0 and not self.real_robot:
            raise InputError("--domain", 0, "1-232 for a simulated robot; domain 0 is a real robot: add --real-robot")
        check_settings(self.damping_time, self.standup_time, self.damping_kd, self.stale, self.tilt)
        number_in("--state-timeout", self.state_timeout, (0.01, 600.0), "s")
        number_in("--final-damping", self.final_damping, (0.0, 60.0), "s")
        if self.replan not in REPLAN_MODES:
            raise InputError("--replan", self.replan, "one of: " + ", ".join(REPLAN_MODES))


@dataclass(frozen=True)
class BrainSummary:
    """What the brain did (``gaitshift dds control --json``).

    Attributes:
        exit_code: 0 or 1 (module docstring). reason: why it ended (the fault, "the plan ended", ...).
        phase: the last phase (``stop`` or ``fault``: damping). ticks: ticks run; locomotion_ticks: of which
        the controller ticked. tick_p50_ms, tick_p99_ms, tick_p999_ms, tick_max_ms: tick durations.
        missed_deadlines: ticks over their deadline. replans: ticks with a re-plan; replan_p50_ms,
        replan_max_ms; locomotion_p50_ms, locomotion_max_ms: the other controller ticks.
        states_received: LowState_ taken; states_dropped: of which dropped for their CRC.
        planned_distance: m, the plan's horizontal CoM travel. wall_time: s. lockstep: the pacing.
        plan_lag_p50, plan_lag_max: ticks a background re-plan's plan came after the tick it was due at
        (NaN inline: none).
    """

    exit_code: int
    reason: str
    phase: str
    ticks: int = 0
    locomotion_ticks: int = 0
    tick_p50_ms: float = math.nan
    tick_p99_ms: float = math.nan
    tick_p999_ms: float = math.nan
    tick_max_ms: float = math.nan
    missed_deadlines: int = 0
    replans: int = 0
    replan_p50_ms: float = math.nan
    replan_max_ms: float = math.nan
    locomotion_p50_ms: float = math.nan
    locomotion_max_ms: float = math.nan
    states_received: int = 0
    states_dropped: int = 0
    planned_distance: float = math.nan
    wall_time: float = 0.0
    lockstep: bool = False
    plan_lag_p50: float = math.nan
    plan_lag_max: float = math.nan

    def as_dict(self) -> dict[str, Any]:
        """The summary as plain values (NaN kept: write it with finite_json)."""
        return asdict(self)


def build_controller(opts: BrainOptions) -> Controller:
    """The controller of ``opts.scenario`` on ``opts.robot`` with ``contact=opts.contact`` and
    ``replan=opts.replan``; its motors must be the hg slots in order (the G1)."""
    ctrl = Controller.from_scenario(opts.scenario, opts.robot, contact=opts.contact, replan=opts.replan)
    check_motor_order(ctrl.motor_names)
    return ctrl


def passive_at_start(state: Any, n: int) -> bool:
    """A real robot may be taken over: every motor of slots 0..n-1 reports mode 0 (disabled), or every one
    a torque under :data:`PASSIVE_TAU` N m (zero torque / damping)."""
    motors = state.motor_state[:n]
    return all(m.mode == 0 for m in motors) or all(abs(m.tau_est) < PASSIVE_TAU for m in motors)


def _safety(ctrl: Controller, opts: BrainOptions) -> Safety:
    """The safety machine of ``ctrl``'s robot: limits from its model and YAML, the start pose's joints."""
    cfg, model = ctrl.robot.robot, ctrl.robot.model
    speed, _ = cfg.speed_limits()
    limits = Limits.of_robot(cfg.joint_names, cfg.joint_range, speed, cfg.torque_limit, ctrl.motor_names)
    kp, kd = standup_gains(limits.tau_max)
    adr = [int(model.joint(name).qposadr[0]) for name in ctrl.motor_names]
    tau = standing_torques(ctrl.robot, ctrl.initial_qpos())
    settings = SafetySettings(kp, kd, tau, opts.damping_time, opts.standup_time, opts.damping_kd, opts.stale, opts.tilt)
    return Safety(limits, settings, ctrl.initial_qpos()[adr])


class _Brain:
    """One run: the controller, the machine, the endpoint, the newest state, the counters."""

    def __init__(self, opts: BrainOptions, ctrl: Controller, endpoint: Endpoint) -> None:
        self.opts, self.ctrl, self.endpoint = opts, ctrl, endpoint
        self.n = len(ctrl.motor_names)
        self.period = ctrl.period
        self.safety = _safety(ctrl, opts)
        self.log = TickLog()
        self.state: Any = None  # the newest LowState_ (StateBytes) with a good CRC
        self.arrival = -math.inf  # perf_counter s when a state of a new tick last arrived
        self.handled = -1  # LowState_.tick of the last state ticked on
        self.written = time.perf_counter()  # when the last command was written
        self.received = self.dropped = self.loco_ticks = 0
        self.last: MotorCommand = self.safety.damping
        self.silent = False  # lockstep: the robot stopped answering (a stale state)

    def take(self) -> bool:
        """Take every state received; keep the newest with a good CRC (a message of another encapsulation is
        dropped as well). True when it is of a new tick."""
        new = False
        for data in self.endpoint.take_bytes():
            self.received += 1
            try:
                msg: StateBytes | None = StateBytes(data)
            except InputError:
                msg = None
            if msg is None or msg.crc != msg.expected_crc():  # the other checks wait for the one ticked on
                self.dropped += 1
                continue
            self.state = msg
            if msg.tick != self.handled:
                new, self.arrival = True, time.perf_counter()
        return new

    def wait_first(self) -> bool:
        """Wait up to ``state_timeout`` s for a first state; True when one came."""
        end = time.perf_counter() + self.opts.state_timeout
        while self.state is None and time.perf_counter() < end:
            self.endpoint.wait(min(0.05, max(end - time.perf_counter(), 0.0)))
            self.take()
        self.written = time.perf_counter()  # the stale clock starts with the first state
        return self.state is not None

    def wait_lockstep(self) -> float:
        """Lockstep: wait for a state of a new tick; the age, s: 0 when one came, else the time since the
        last command (>= ``stale``). A repeat of the state ticked on gets nothing: one command per state
        (the robot steps once per command received; the writer is reliable, so a command is not lost but
        with the robot, and then the state goes stale)."""
        limit = self.opts.stale
        while True:
            if self.take() or self.state.tick != self.handled:  # the state held may be new (the first one)
                return 0.0
            age = time.perf_counter() - self.written
            if self.silent and self.safety.ended:  # no robot to wait for: damping written every period
                self.endpoint.wait(self.period)
                self.take()
                return age
            if age > limit:
                self.silent = True
                return age
            self.endpoint.wait(limit - age)

    def frame(self, t: float) -> tuple[SensorFrame | None, str]:
        """The newest state as a frame at ``t`` s, or None and why (a NaN or out-of-range field)."""
        try:
            return frame_from_lowstate(self.state, t, self.n), ""
        except InputError as e:
            return None, f"state out of range: {e}"

    def write(self, cmd: MotorCommand) -> None:
        self.endpoint.write_bytes(lowcmd_bytes(cmd, self.state.mode_machine))
        self.written, self.last = time.perf_counter(), cmd

    def control(self, t: float, age: float) -> int:
        """One tick at machine time ``t`` s with a state ``age`` s old: the command written; the tick's kind
        for the log (0 safety phase, 1 controller, 2 controller with a re-plan)."""
        frame, why = self.frame(t)
        if frame is None:
            self.safety.fault(t, why)
            cmd: MotorCommand | None = self.safety.damping
        else:
            cmd = self.safety.step(t, frame, age)
        kind = 0
        if cmd is None and frame is not None:
            cmd, kind = self.locomotion(t, frame)
        self.handled = self.state.tick
        self.write(cmd if cmd is not None else self.safety.damping)
        return kind

    def locomotion(self, t: float, frame: SensorFrame) -> tuple[MotorCommand, int]:
        """The controller's tick at its own clock (zero when the stand-up ended), guarded; the plan's end
        stops the machine (damping from this tick)."""
        tl = t - self.safety.locomotion_start
        if self.ctrl.finished(tl):
            self.safety.stop(t)
            return self.safety.damping, 0
        before = self.ctrl.trajectory
        try:
            raw = self.ctrl.tick(replace(frame, t=tl))
        except GaitshiftError as e:
            self.safety.fault(t, f"controller: {e}")
            return self.safety.damping, 0
        self.loco_ticks += 1
        return self.safety.guard(raw, frame, t), 2 if self.ctrl.trajectory is not before else 1


def _loop(brain: _Brain, signals: StopSignals) -> None:
    """Tick until ``final_damping`` s of the machine's clock after it ended (module docstring)."""
    opts, period, safety = brain.opts, brain.period, brain.safety
    wall0 = time.perf_counter()
    k = 0
    while True:
        if opts.lockstep:
            age = brain.wait_lockstep()
            t, due = k * period, time.perf_counter()
            start = due
        else:
            due = wall0 + k * period
            time.sleep(max(due - time.perf_counter(), 0.0))
            start = time.perf_counter()
            brain.take()
            t = start - wall0
            age = time.perf_counter() - brain.arrival
        if safety.ended and t - safety.since >= opts.final_damping - 0.5 * period:
            return
        if signals.why:
            safety.stop(t, f"stopped by {signals.why}")
        kind = brain.control(t, age)
        end = time.perf_counter()
        missed = end - start > period if opts.lockstep else end - due > period
        brain.log.add(end - start, kind, missed)
        k = k + 1 if opts.lockstep else max(k + 1, math.ceil((end - wall0) / period))


def _summary(brain: _Brain | None, code: int, reason: str, phase: str, wall: float) -> BrainSummary:
    if brain is None:
        return BrainSummary(code, reason, phase, wall_time=wall)
    s = brain.log.stats()
    com = brain.ctrl.trajectory.com_pos
    lags = np.asarray(getattr(brain.ctrl.replan, "lags", []), float)
    return BrainSummary(
        code,
        reason,
        phase,
        s.ticks,
        brain.loco_ticks,
        s.p50,
        s.p99,
        s.p999,
        s.max,
        s.missed,
        s.replans,
        s.replan_p50,
        s.replan_max,
        s.other_p50,
        s.other_max,
        brain.received,
        brain.dropped,
        float(np.linalg.norm(com[-1, :2] - com[0, :2])),
        wall,
        brain.opts.lockstep,
        float(np.median(lags)) if len(lags) else math.nan,
        float(lags.max()) if len(lags) else math.nan,
    )


def run_brain(opts: BrainOptions, endpoint: Endpoint | None = None, ctrl: Controller | None = None) -> BrainSummary:
    """Run the brain (module docstring) until the plan ended, a fault, or SIGINT/SIGTERM."""
    ctrl = ctrl or build_controller(opts)
    start = time.perf_counter()
    endpoint = endpoint or open_endpoint(opts.domain, opts.iface, "controller")
    brain = _Brain(opts, ctrl, endpoint)
    where = f"DDS domain {opts.domain} over {opts.iface}"
    if not brain.wait_first():
        reason = (
            f"no rt/lowstate from the robot within {opts.state_timeout:g} s on {where}: is the robot process running?"
        )
        return _summary(None, 1, reason, "damping", time.perf_counter() - start)
    if opts.real_robot and not passive_at_start(LowState_.deserialize(brain.state.data), brain.n):
        reason = "refused: the robot is not damping or zero-torque (every motor mode 0 or |tau_est| < 1 N m) at start"
        return _summary(None, 1, reason, "damping", time.perf_counter() - start)
    signals = StopSignals()
    try:
        _loop(brain, signals)
    finally:
        signals.restore()
    s = brain.safety
    code = 0 if s.phase == "stop" else 1
    return _summary(brain, code, s.reason, s.phase, time.perf_counter() - start)
