"""The options and the summary of the brain ``gaitshift dds control`` (:mod:`gaitshift.dds.brain`)."""

import math
from dataclasses import asdict, dataclass
from typing import Any

from gaitshift.control.estimation.calibration import CALIBRATION_TIME
from gaitshift.control.replanner import REPLAN_MODES
from gaitshift.dds.priority import check_priority
from gaitshift.dds.realtime import DEADLINE, DEADLINE_RANGE
from gaitshift.dds.record import check_record
from gaitshift.dds.safety import check_settings
from gaitshift.dds.transport import check_domain
from gaitshift.errors import InputError, check_choice, check_flag, number_in
from gaitshift.scenario.sim_settings import LATENCY_RANGE

__all__ = ["BrainOptions", "BrainSummary"]


@dataclass(frozen=True)
class BrainOptions:
    """Options of ``gaitshift dds control`` (:mod:`gaitshift.dds.brain`; the safety ones:
    :class:`~gaitshift.dds.safety.SafetySettings`).

    Attributes:
        scenario: built-in name or YAML. robot: robot name or YAML (None: the scenario's).
        domain: DDS domain id (0: a real robot, only with ``real_robot``). iface: network interface.
        lockstep: one tick per robot tick (:mod:`gaitshift.dds.lockstep`). deadline: real time: periods
        after a tick's start that the next waits for a state (:mod:`gaitshift.dds.realtime`).
        state_timeout: s to wait for the first state. real_robot: allow domain 0; refuse unless the robot
        is passive at start (:func:`~gaitshift.dds.brain_setup.passive_at_start`).
        stale: s. damping_time, standup_time: s. damping_kd: N m s/rad. tilt: rad.
        final_damping: s of damping written after ``stop`` or ``fault`` before exiting.
        contact: the controller's contact detection ("torque": no foot force needed).
        replan: where the controller re-plans (:mod:`gaitshift.control.replanner`; "process": off the tick).
        hold: s of the still hold after the stand-up; its gyro readings calibrate the controller (0: none;
            the default is the simulation's standstill, ``CALIBRATION_TIME``).
        calibrate: feed the hold's gyro readings to ``Controller.calibrate`` (False: the hold only).
        cmd_topic: take live velocity commands from ``rt/gaitshift/cmd_vel`` (:mod:`gaitshift.dds.cmdvel`).
        diag_every: write the state estimate on ``rt/gaitshift/estimate`` every this many ticks (0: never).
        latency: ticks from the brain's tick to its command acting, which the controller predicts across
            beside the state's own age (``ControllerSettings.latency``: the command's way to the motors;
            in lockstep the robot applies it at the tick it answers, 0; in real time at its next tick, 1,
            plus the link's delay, which the brain cannot see). None: 0 in lockstep, 1 in real time
            (:attr:`command_latency`).
        rt_priority: run the tick's thread under SCHED_FIFO at this priority (:mod:`gaitshift.dds.priority`;
            None: a normal thread).
        known_floor: the robot stands on a flat floor, whose height the estimator then takes as a
            measurement when the scenario has no terrain (``ControllerSettings.floor``); False: unknown.
        record: a ``.npz`` to write the run's recording to, a row per tick (:mod:`gaitshift.dds.record`);
            None: none.
    """

    scenario: str
    robot: str | None = None
    domain: int = 1
    iface: str = "lo"
    lockstep: bool = False
    deadline: float = DEADLINE
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
    hold: float = CALIBRATION_TIME
    calibrate: bool = True
    cmd_topic: bool = False
    diag_every: int = 1
    latency: int | None = None
    known_floor: bool = False
    rt_priority: int | None = None
    record: str | None = None

    def __post_init__(self) -> None:
        check_domain(self.domain)
        check_record(self.record)
        if self.domain == 0 and not self.real_robot:
            raise InputError("--domain", 0, "1-232 for a simulated robot; domain 0 is a real robot: add --real-robot")
        check_settings(self.damping_time, self.standup_time, self.damping_kd, self.stale, self.tilt)
        number_in("--state-timeout", self.state_timeout, (0.01, 600.0), "s")
        number_in("--final-damping", self.final_damping, (0.0, 60.0), "s")
        check_choice("--replan", self.replan, REPLAN_MODES)
        number_in("--hold", self.hold, (0.0, 60.0), "s")
        number_in("--deadline", self.deadline, DEADLINE_RANGE, "periods")
        if self.latency is not None:
            if isinstance(self.latency, bool) or not isinstance(self.latency, int):
                raise InputError("--latency", self.latency, "an integer number of ticks")
            number_in("--latency", self.latency, LATENCY_RANGE, "ticks")
        check_flag("--known-floor", self.known_floor)
        check_priority(self.rt_priority, "--rt-priority")
        if isinstance(self.diag_every, bool) or not isinstance(self.diag_every, int) or self.diag_every < 0:
            raise InputError("--diag-every", self.diag_every, "an integer >= 0 (0: no diagnostics)")

    @property
    def command_latency(self) -> int:
        """The ticks the controller predicts across: ``latency``, or by default 0 in lockstep and 1 in real
        time (a command computed on a state's arrival acts at the robot's next tick)."""
        if self.latency is not None:
            return self.latency
        return 0 if self.lockstep else 1


@dataclass(frozen=True)
class BrainSummary:
    """What the brain did (``gaitshift dds control --json``).

    Attributes:
        exit_code: 0 or 1 (module docstring). reason: why it ended (the fault, "the plan ended", ...).
        phase: the last phase (``stop`` or ``fault``: damping). ticks: ticks run; locomotion_ticks: of which
        the controller ticked. tick_p50_ms, tick_p99_ms, tick_p999_ms, tick_max_ms: tick durations.
        missed_deadlines: ticks over their deadline. replans: ticks with a re-plan; replan_p50_ms,
        replan_max_ms; locomotion_p50_ms, locomotion_max_ms: the other controller ticks.
        states_received: LowState_ taken; states_dropped: of which dropped for their CRC;
        states_measured_only: of which the controller measured but did not act on (a newer one came with
        them, :meth:`gaitshift.control.controller.Controller.measure`).
        planned_distance: m, the plan's horizontal CoM travel. wall_time: s. lockstep: the pacing.
        plan_lag_p50, plan_lag_max: ticks a background re-plan's plan came after the tick it was due at
        (NaN inline: none).
        calibration_samples: readings of the hold the gyro calibration took (0: not calibrated).
        commands_received, commands_accepted, commands_dropped, commands_applied: live commands (of
        ``rt/gaitshift/cmd_vel``, the browser page and the keys) taken, valid, refused (NaN, out of range,
        after a stop), handed to the controller;
        command_error: the last refusal's line. estimates_written: ``rt/gaitshift/estimate`` samples.
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
    states_measured_only: int = 0
    planned_distance: float = math.nan
    wall_time: float = 0.0
    lockstep: bool = False
    plan_lag_p50: float = math.nan
    plan_lag_max: float = math.nan
    calibration_samples: int = 0
    commands_received: int = 0
    commands_accepted: int = 0
    commands_dropped: int = 0
    commands_applied: int = 0
    command_error: str = ""
    estimates_written: int = 0

    def as_dict(self) -> dict[str, Any]:
        """The summary as plain values (NaN kept: write it with finite_json)."""
        return asdict(self)
