"""The brain over DDS: :class:`gaitshift.Controller` fed from ``rt/lowstate``, writing ``rt/lowcmd``, behind
the safety state machine (:mod:`gaitshift.dds.safety`).

Each tick::

    take rt/lowstate                  the newest state with a good CRC (bad CRCs dropped and counted), as bytes
    frame_from_lowstate(...)          a NaN or out-of-range field: a fault
    take the live commands            --cmd-topic, --web, --teleop: checked, the newest valid one kept
    safety.step(t, frame, age)        damping -> stand-up -> hold -> locomotion -> stop, or a fault: damping
    ctrl.tick(frame)                  locomotion only; its clock starts when the hold ends
    safety.guard(cmd, frame)          q, dq, torque clamped to the robot's limits
    lowcmd_bytes(cmd, mm)             mode 1 on every motor, mode_machine from the state, the CRC set
    write rt/lowcmd
    write rt/gaitshift/estimate       every diag_every ticks: the estimate (:mod:`gaitshift.dds.diagnostics`)
    hand the tick to the page         --web: phase, record, plan (:mod:`gaitshift.dds.brain_web`)

The gyro readings of the hold (the robot standing still at the start pose, ``hold`` s) are the
controller's calibration (``Controller.calibrate``), fed before its first tick. Live commands
(:mod:`gaitshift.dds.cmdvel`: the topic, and the queues of the browser page and the keyboard that
``run_brain`` is given) reach the controller at the locomotion ticks, through its ``command`` and ``stop``.
The brain reads ``rt/lowstate`` and ``rt/gaitshift/cmd_vel`` only: nothing of the robot's truth.

The states are read and the commands written as their CDR bytes (:mod:`gaitshift.dds.cdr`: the same
bytes as cyclonedds's (de)serialization, in a tenth of its time).

Pacing: real time by default, a tick on each state's arrival (:mod:`gaitshift.dds.realtime`: the clock the
robot's, its tick less the first state's, in periods; when no state of a new tick came within ``deadline``
periods of the last tick's start, the safety checks the state held and the last command is written again);
with ``lockstep`` one tick per robot tick (the robot's ``rt/gaitshift/clock``, :mod:`gaitshift.dds.lockstep`:
a tick that brought no new state ticks the controller on the one held), the clock the robot's too, and the
robot is silent (a stale state) when no clock came within ``stale`` s of the last command. A tick's duration
runs from its start (real time: a state's arrival or the deadline; lockstep: the robot tick's arrival) to the
command written; a tick longer than a period missed its deadline. The run ends ``final_damping`` s of the
machine's clock after it entered ``stop`` or ``fault``. A state's age, for the stale limit, is the time since
a state of a new tick was last taken: on the wall clock in real time, in robot ticks in lockstep. The
controller gets the readings' own time (the state's tick) and their age in ticks.
Exit codes (:attr:`BrainSummary.exit_code`): 0 the plan ended (or SIGINT/SIGTERM) and the robot damps; 1 a
fault, no state within ``state_timeout`` s, or a real robot that is not damping at start.
"""

import math
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from gaitshift.control.controller import Controller
from gaitshift.control.frames import MotorCommand, SensorFrame
from gaitshift.control.state import MAX_BRIDGE
from gaitshift.dds.brain_options import BrainOptions, BrainSummary
from gaitshift.dds.brain_setup import build_controller, passive_at_start, safety_of
from gaitshift.dds.brain_web import BrainFeed
from gaitshift.dds.cdr import StateBytes
from gaitshift.dds.cmdvel import CommandInput, CommandSource, TopicSource, live_limits
from gaitshift.dds.convert import frame_from_lowstate, lowcmd_bytes
from gaitshift.dds.diagnostics import Diagnostics
from gaitshift.dds.lockstep import LockstepClock, ticks_from
from gaitshift.dds.messages import LowState_
from gaitshift.dds.priority import set_priority
from gaitshift.dds.realtime import ArrivalClock
from gaitshift.dds.record import Recorder, brain_row, brain_widths
from gaitshift.dds.safety import PHASES
from gaitshift.dds.signals import StopSignals
from gaitshift.dds.still_gyro import LegRate
from gaitshift.dds.ticklog import TickLog
from gaitshift.dds.transport import Endpoint, open_endpoint
from gaitshift.errors import GaitshiftError, InputError

__all__ = ["BrainOptions", "BrainSummary", "run_brain"]


class _Brain:
    """One run: the controller, the machine, the endpoint, the newest state, the counters."""

    def __init__(
        self,
        opts: BrainOptions,
        ctrl: Controller,
        endpoint: Endpoint,
        say: Callable[[str], None],
        live: tuple[Sequence[CommandSource], BrainFeed | None] = ((), None),
    ) -> None:
        self.opts, self.ctrl, self.endpoint = opts, ctrl, endpoint
        sources = [*([TopicSource(endpoint)] if opts.cmd_topic else []), *live[0]]
        limits = live_limits(ctrl, opts.scenario) if sources else None
        self.commands = None if limits is None else CommandInput(sources, limits, say)
        self.page = live[1]
        self.diag = Diagnostics(endpoint, opts.diag_every) if opts.diag_every else None
        self.hold: list[tuple[float, np.ndarray, np.ndarray]] = []  # the hold's (t s, gyro rad/s, q rad)
        self.legs = (
            LegRate(ctrl.robot.model, ctrl.imu_site, ctrl.foot_bodies, ctrl.motor_names) if ctrl.imu_site else None
        )
        self.calibrated = -1  # the readings fed to the calibration (-1: not yet done)
        self.n = len(ctrl.motor_names)
        self.period = ctrl.period
        self.safety = safety_of(ctrl, opts)
        self.log = TickLog()
        self.state: Any = None  # the newest LowState_ (StateBytes) with a good CRC
        self.overtaken: list[Any] = []  # states of new ticks a newer one overtook before a tick, oldest first
        self.measured_only = 0  # of which the controller measured (locomotion)
        self.arrival = -math.inf  # perf_counter s when a state of a new tick last arrived
        self.taken = 0.0  # machine time s when the readings of the state held were taken, as far as known
        self.handled = -1  # LowState_.tick of the last state ticked on
        self.tick0 = 0  # LowState_.tick of the first state
        self.written = time.perf_counter()  # when the last command was written
        self.received = self.dropped = self.loco_ticks = 0
        self.last: MotorCommand = self.safety.damping
        self.silent = False  # lockstep: the robot stopped answering (a stale state)
        self.clock = LockstepClock(endpoint) if opts.lockstep else None  # lockstep: the robot's ticks
        self.fresh = True  # real time: this tick brought a state of a new tick (else its deadline passed)
        self.frame_now: SensorFrame | None = None  # the frame of this tick's state (None: out of range)
        m = ctrl.robot.model
        meta = {"process": "brain", "scenario": opts.scenario, "period": self.period, "motors": ctrl.motor_names}
        self.recorder = Recorder(opts.record, brain_widths(self.n, m.nq, m.nv), meta) if opts.record else None

    def take(self) -> bool:
        """Take every state received; keep the newest with a good CRC (a message of another encapsulation is
        dropped as well), and the ones of new ticks it overtook for :meth:`measure`. True when it is of a new
        tick."""
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
            if self.state is not None and self.state.tick not in (self.handled, msg.tick):
                self.overtaken.append(self.state)
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
        self.tick0 = 0 if self.state is None else self.state.tick
        return self.state is not None

    def wait_lockstep(self) -> tuple[float, int | None]:
        """Lockstep (:mod:`gaitshift.dds.lockstep`): wait for the robot's next tick and the state it names;
        that tick and the held state's age, s. Without a clock within ``stale`` s of the last command (the
        robot silent): None and the time since that command. One command per robot tick: the robot steps
        once per command (the writer is reliable, so a command is not lost but with the robot, and then the
        state goes stale)."""
        assert self.clock is not None
        limit = self.opts.stale
        while True:
            self.take()
            tick = self.clock.due(None if self.state is None else self.state.tick)
            if tick is not None:
                self.taken = ticks_from(self.tick0, self.state.tick) * self.period
                return self.clock.age(self.period), tick
            age = time.perf_counter() - self.written
            if self.silent and self.safety.ended:  # no robot to wait for: damping written every period
                self.endpoint.wait(self.period)
                self.take()
                return age, None
            if age > limit:
                self.silent = True
                return age, None
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
        self.frame_now = frame
        if self.commands is not None:
            self.commands.poll()
        if frame is None:
            self.safety.fault(t, why)
            cmd: MotorCommand | None = self.safety.damping
        else:
            cmd = self.safety.step(t, frame, age)
            fresh = not self.hold or self.hold[-1][0] != self.taken  # a held state is one reading
            if self.safety.phase == "hold" and self.legs is not None and self.opts.calibrate and fresh:
                self.hold.append((self.taken, frame.imu_gyro, frame.q))
        kind = 0
        if cmd is None and frame is not None:
            cmd, kind = self.locomotion(t, frame)
        new, self.handled = self.state.tick != self.handled, self.state.tick
        self.overtaken = []  # measured by the controller's tick, or before it ticks
        self.write(cmd if cmd is not None else self.safety.damping)
        if self.diag is not None and new:  # one estimate per state acted on
            record = self.ctrl.record if kind else None
            self.diag.publish(self.handled, t, self.safety.phase, None if record is None else record.estimate)
        if self.page is not None:
            self.page.offer(self.safety.phase, self.ctrl.record if kind else None, self.ctrl.trajectory)
        return kind

    def calibrate(self, t: float) -> bool:
        """Before the controller's first tick: its gyro calibration from the hold's readings
        (:mod:`gaitshift.dds.still_gyro`; fewer than two samples: none); False, and a fault at ``t`` s,
        when the controller refuses them."""
        hold, self.hold = self.hold, []
        samples, period = np.zeros((0, 3)), 0.0
        if self.legs is not None and hold:
            times, gyro, q = (np.array(column) for column in zip(*hold, strict=True))
            samples, period = self.legs.samples(times, gyro, q)
        self.calibrated = len(hold) if len(samples) >= 2 else 0
        if not self.calibrated:
            return True
        try:
            self.ctrl.calibrate(samples, period)
        except GaitshiftError as e:
            self.safety.fault(t, f"calibration: {e}")
            return False
        return True

    def measure(self, t: float, taken: float) -> bool:
        """The states a newer one overtook (the held one's readings at ``taken`` s of the controller's clock),
        measured by the controller, oldest first; False, and a fault at ``t`` s, on one out of range."""
        newest, overtaken, self.overtaken = self.state.tick, self.overtaken, []
        for msg in overtaken:
            back = ticks_from(msg.tick, newest) * self.period
            if taken - back < 0.0:  # before the controller's first tick
                continue
            try:
                frame = frame_from_lowstate(msg, taken - back, self.n)
            except InputError as e:
                self.safety.fault(t, f"state out of range: {e}")
                return False
            self.ctrl.measure(frame)
            self.measured_only += 1
        return True

    def locomotion(self, t: float, frame: SensorFrame) -> tuple[MotorCommand, int]:
        """The controller's tick at its own clock (zero when the stand-up ended), guarded; the plan's end
        stops the machine (damping from this tick)."""
        tl = t - self.safety.locomotion_start
        if self.ctrl.finished(tl):
            self.safety.stop(t)
            return self.safety.damping, 0
        if self.calibrated < 0 and not self.calibrate(t):
            return self.safety.damping, 0
        if not self.fresh and self.loco_ticks:  # real time, no new state: the last command again (realtime.py)
            return self.last, 0
        before = self.ctrl.trajectory
        taken = max(self.taken - self.safety.locomotion_start, 0.0)  # the readings' time on the controller's clock
        age = min(max(round((tl - taken) / self.period), 0), MAX_BRIDGE)
        try:
            if not self.measure(t, taken):
                return self.safety.damping, 0
            if self.commands is not None:
                self.commands.apply(self.ctrl)
            raw = self.ctrl.tick(replace(frame, t=taken), age)
        except GaitshiftError as e:
            self.safety.fault(t, f"controller: {e}")
            return self.safety.damping, 0
        self.loco_ticks += 1
        return self.safety.guard(raw, frame, t), 2 if self.ctrl.trajectory is not before else 1


def _loop(brain: _Brain, signals: StopSignals) -> None:
    """Tick until ``final_damping`` s of the machine's clock after it ended (module docstring)."""
    opts, period, safety = brain.opts, brain.period, brain.safety
    clock = ArrivalClock(period, opts.deadline)
    first, t = True, 0.0
    while True:
        if opts.lockstep:
            age, tick = brain.wait_lockstep()
            # the robot's clock; without it (the robot silent) the machine's goes on by periods
            t = ticks_from(brain.tick0, tick) * period if tick is not None else t + period
            start = time.perf_counter()
        else:  # on each state's arrival (gaitshift.dds.realtime)
            brain.fresh = clock.wait(brain.take, brain.endpoint.wait) or first
            start = clock.start
            t = clock.tick(brain.fresh, brain.tick0, brain.state.tick)
            if brain.fresh:
                brain.taken = t
            age = start - brain.arrival
        first = False
        if safety.ended and t - safety.since >= opts.final_damping - 0.5 * period:
            return
        if signals.why:
            safety.stop(t, f"stopped by {signals.why}")
        kind = brain.control(t, age)
        duration = time.perf_counter() - start
        missed = duration > period
        brain.log.add(duration, kind, missed)
        if brain.recorder is not None:
            record(brain, t, duration, kind, missed)


def record(brain: _Brain, t: float, duration: float, kind: int, missed: bool) -> None:
    """The tick's row of the recording (:mod:`gaitshift.dds.record`), as the tick log has it."""
    assert brain.recorder is not None
    rec = brain.ctrl.record if kind else None
    scalars = {"t": t, "duration": duration, "missed": missed, "fresh": brain.fresh, "kind": kind}
    phase = PHASES.index(brain.safety.phase)
    brain.recorder.add(**brain_row(brain.handled, brain.frame_now, brain.last, rec, phase=phase, **scalars))


def _summary(brain: _Brain | None, code: int, reason: str, phase: str, wall: float) -> BrainSummary:
    if brain is None:
        return BrainSummary(code, reason, phase, wall_time=wall)
    s = brain.log.stats()
    com = brain.ctrl.whole_plan().com_pos
    lags = np.asarray(getattr(brain.ctrl.replan, "lags", []), float)
    cmds = brain.commands
    return BrainSummary(
        code,
        reason,
        phase,
        ticks=s.ticks,
        locomotion_ticks=brain.loco_ticks,
        tick_p50_ms=s.p50,
        tick_p99_ms=s.p99,
        tick_p999_ms=s.p999,
        tick_max_ms=s.max,
        missed_deadlines=s.missed,
        replans=s.replans,
        replan_p50_ms=s.replan_p50,
        replan_max_ms=s.replan_max,
        locomotion_p50_ms=s.other_p50,
        locomotion_max_ms=s.other_max,
        states_received=brain.received,
        states_dropped=brain.dropped,
        states_measured_only=brain.measured_only,
        planned_distance=float(np.linalg.norm(com[-1, :2] - com[0, :2])),
        wall_time=wall,
        lockstep=brain.opts.lockstep,
        plan_lag_p50=float(np.median(lags)) if len(lags) else math.nan,
        plan_lag_max=float(lags.max()) if len(lags) else math.nan,
        calibration_samples=max(brain.calibrated, 0),
        commands_received=cmds.received if cmds else 0,
        commands_accepted=cmds.accepted if cmds else 0,
        commands_dropped=cmds.dropped if cmds else 0,
        commands_applied=cmds.applied if cmds else 0,
        command_error=cmds.last_error if cmds else "",
        estimates_written=brain.diag.written if brain.diag else 0,
    )


def _stderr(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def run_brain(
    opts: BrainOptions,
    endpoint: Endpoint | None = None,
    ctrl: Controller | None = None,
    say: Callable[[str], None] = _stderr,
    queues: Sequence[CommandSource] = (),
    page: BrainFeed | None = None,
) -> BrainSummary:
    """Run the brain (module docstring) until the plan ended, a fault, or SIGINT/SIGTERM; ``say`` takes the
    lines of the run (a dropped live command). ``queues``: command sources beside the topic (the browser
    page's, the keyboard's: :class:`~gaitshift.dds.cmdvel.CommandQueue`); ``page``: the browser page's
    hand-off (:class:`~gaitshift.dds.brain_web.BrainFeed`), given every tick."""
    ctrl = ctrl or build_controller(opts)
    start = time.perf_counter()
    endpoint = endpoint or open_endpoint(opts.domain, opts.iface, "controller")
    brain = _Brain(opts, ctrl, endpoint, say, (queues, page))
    where = f"DDS domain {opts.domain} over {opts.iface}"
    if not brain.wait_first():
        reason = (
            f"no rt/lowstate from the robot within {opts.state_timeout:g} s on {where}: is the robot process running?"
        )
        return _summary(None, 1, reason, "damping", time.perf_counter() - start)
    if opts.real_robot and not passive_at_start(LowState_.deserialize(brain.state.data), brain.n):
        reason = "refused: the robot is not damping or zero-torque (every motor mode 0 or |tau_est| < 1 N m) at start"
        return _summary(None, 1, reason, "damping", time.perf_counter() - start)
    set_priority(opts.rt_priority, "--rt-priority")
    signals = StopSignals()
    try:
        _loop(brain, signals)
    finally:
        signals.restore()
        if brain.recorder is not None:
            brain.recorder.save()
    s = brain.safety
    code = 0 if s.phase == "stop" else 1
    return _summary(brain, code, s.reason, s.phase, time.perf_counter() - start)
