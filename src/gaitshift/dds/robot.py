"""The robot process: gaitshift's MuJoCo world (:class:`~gaitshift.sim.world.World` on the plant of
:func:`~gaitshift.sim.plant.build_plant`) behind Unitree's low-level protocol, a stand-in for a G1.

Every control period ``dt`` (the physics step, 2 ms)::

    world.observe(k)                       the truth: the fall test, the pelvis position
    state = lowstate_from_frame(...)       the world's SensorFrame as a LowState_ (tick = k), the CRC set
    link.take(k, state)                    faults on the link: dropped, corrupted, delayed (link.py)
    endpoint.writer.write(...)             rt/lowstate: the states the link releases at tick k
    take rt/lowcmd                         every LowCmd_ received: counted; a bad CRC or a bad field dropped
    world.apply(command)                   tau + kp (q_des - q) + kd (dq_des - dq) per motor
    world.step()
    take rt/gaitshift/estimate             the brain's estimates, scored against the truth kept per tick

The robot scores the brain's state estimate (:mod:`gaitshift.dds.scoring`) when the brain writes it: the
truth stays in this process, nothing of it is written on DDS.

The command applied is the newest valid one; when none has come for ``damping_after`` s (or none yet) the
motors damp: ``kp = 0``, ``kd = damping_kd``, ``tau = 0``. Pacing: real time by default (tick k at
``t0 + k dt`` on the wall clock; a late tick moves ``t0`` on by its lateness, and one over a period late
is counted); with ``lockstep``, once a first intact
state is written, every tick writes the robot's clock (``rt/gaitshift/clock``: the tick and the newest
intact state written so far, :mod:`gaitshift.dds.lockstep`) and the world steps only when a valid command
has arrived after it (the state and the clock written again every ``resend`` s of wall time meanwhile), so
the controller may take its time, and it ticks once per robot tick, as in real time: on a tick that
releases no intact state (one in flight, dropped or corrupted) it ticks on the state it holds; on a tick
that releases several (a delay that shrank: the link keeps their order) it measures the older ones and
acts on the newest, which the clock names, so that a run repeats whatever the machine's scheduling. The run
holds in real time until a first valid command has come (``gantry``): its ticks count on and their states are
written, but the world does not step, as a robot held in its gantry while the brain starts (how long the
brain and the robot take to find each other on DDS varies; a G1 in damping folds in a fraction of a second).
The run ends after ``duration`` s of ticks, or at SIGINT/SIGTERM (:func:`run_robot` returns the summary either way).
"""

import copy
import math
import time
from dataclasses import asdict, dataclass, field, fields
from typing import Any

import numpy as np

from gaitshift.control.frames import MotorCommand
from gaitshift.dds.convert import command_from_lowcmd, lowstate_from_frame
from gaitshift.dds.g1 import check_motor_order
from gaitshift.dds.link import Link, LinkFaults
from gaitshift.dds.own_messages import CLOCK_TOPIC, ESTIMATE_TOPIC, Clock_, Estimate_
from gaitshift.dds.priority import check_priority, set_priority
from gaitshift.dds.record import Recorder, check_record, command_values, robot_widths
from gaitshift.dds.scoring import EstimateScore, ScoreSummary
from gaitshift.dds.signals import StopSignals
from gaitshift.dds.transport import Endpoint, check_domain, open_endpoint, topic_reader, topic_writer
from gaitshift.errors import InputError, number_in
from gaitshift.models.terrain import FLAT, Terrain
from gaitshift.robots.model import standing_qpos
from gaitshift.scenario import load_scenario
from gaitshift.scenario.terrain import world_ground
from gaitshift.sim.loop import SimOptions
from gaitshift.sim.plant import build_plant
from gaitshift.sim.world import World, with_floor_friction

__all__ = ["RobotOptions", "RobotSummary", "run_robot"]


@dataclass(frozen=True)
class RobotOptions:
    """Options of the robot process (module docstring).

    Attributes:
        robot: built-in robot name or YAML (its motors must be the hg slots in order: the G1).
        domain: DDS domain id (1: Unitree's simulator default; 0 is the real robot's network).
        iface: network interface (``lo``: nothing leaves the machine).
        duration: simulated seconds to run, or None: until SIGINT/SIGTERM.
        lockstep: step only when a command for this tick's clock has arrived (else real time).
        gantry: real time: the world holds still (no physics step) until the first valid command.
        damping_after: s without a valid command before the motors damp.
        damping_kd: N m s/rad, the damping gain.
        mode_machine: the hardware variant reported in every LowState_.
        noise: the world's sensor noise profile (``none``, ``typical``, ``rl-peer``).
        resend: lockstep only: s of wall time between repeats of the state while no command comes.
        control_period: s, the physics step and the period of the states.
        faults: what the link does to the states (:mod:`gaitshift.dds.link`).
        world: a scenario (built-in name or YAML) whose ``terrain:`` the world is built on, and whose
            ``sim: {friction}`` the floor takes; None: a flat floor of the model's friction.
        rt_priority: run the loop's thread under SCHED_FIFO at this priority (:mod:`gaitshift.dds.priority`;
            None: a normal thread).
        record: a ``.npz`` to write the run's recording to, a row per tick (:mod:`gaitshift.dds.record`).
    """

    robot: str = "g1"
    domain: int = 1
    iface: str = "lo"
    duration: float | None = None
    lockstep: bool = False
    gantry: bool = True
    damping_after: float = 0.1
    damping_kd: float = 2.0
    mode_machine: int = 0
    noise: str = "none"
    resend: float = 0.02
    control_period: float = 0.002
    faults: LinkFaults = field(default_factory=LinkFaults)
    world: str | None = None
    rt_priority: int | None = None
    record: str | None = None

    def __post_init__(self) -> None:
        check_domain(self.domain)
        check_record(self.record)
        if self.duration is not None:
            number_in("--duration", self.duration, (0.0, 1e6), "s")
        number_in("--damping-after", self.damping_after, (0.0, 60.0), "s")
        number_in("--damping-kd", self.damping_kd, (0.0, 100.0), "N m s/rad")
        number_in("--resend", self.resend, (1e-3, 10.0), "s")
        if isinstance(self.mode_machine, bool) or not isinstance(self.mode_machine, int):
            raise InputError("--mode-machine", self.mode_machine, "an integer in [0, 255]")
        number_in("--mode-machine", self.mode_machine, (0, 255))
        check_priority(self.rt_priority, "--rt-priority")
        scenario_world(self.world)  # a bad scenario: one InputError before any DDS traffic


@dataclass
class RobotSummary:
    """What the robot process did (written as JSON by ``gaitshift dds robot --summary``).

    Attributes:
        fell: the world's fall test fired; fall_time: s of simulated time at the first fall (NaN: none);
        fall_reason: its reason. distance: m, horizontal pelvis displacement from the start.
        sim_time: s of ticks (a gantry's hold included); ticks: ticks; held_ticks: of which the gantry
        held (no physics step); wall_time: s.
        states_published: LowState_ written (repeats in lockstep included).
        packets_received: LowCmd_ received; packets_dropped: of which dropped (a bad CRC or a bad field);
        crc_rejects: of which dropped for their CRC. commands_applied: ticks driven by a received command;
        damping_ticks: ticks in damping. late_ticks: real time only: ticks that started over a period late.
        link_dropped, link_corrupted: states the link dropped, wrote with a wrong CRC;
        link_delay_ticks_mean, link_delay_ticks_max: ticks from a state's tick to its writing (NaN: none).
        stopped_by: "duration" or the signal's name.
        estimates_received ... est_position_drift: the brain's estimate scored against the truth
        (:class:`~gaitshift.dds.scoring.ScoreSummary`; NaN when none was scored).
    """

    fell: bool = False
    fall_time: float = math.nan
    fall_reason: str = ""
    distance: float = 0.0
    sim_time: float = 0.0
    ticks: int = 0
    held_ticks: int = 0
    wall_time: float = 0.0
    states_published: int = 0
    packets_received: int = 0
    packets_dropped: int = 0
    crc_rejects: int = 0
    commands_applied: int = 0
    damping_ticks: int = 0
    late_ticks: int = 0
    link_dropped: int = 0
    link_corrupted: int = 0
    link_delay_ticks_mean: float = math.nan
    link_delay_ticks_max: int = 0
    stopped_by: str = ""
    estimates_received: int = 0
    estimates_scored: int = 0
    estimates_unmatched: int = 0
    est_velocity_rmse: float = math.nan
    est_tilt_rmse: float = math.nan
    est_height_rmse: float = math.nan
    est_contact_accuracy: float = math.nan
    est_yaw_drift: float = math.nan
    est_position_drift: float = math.nan
    last_error: str = field(default="", repr=False)

    def as_dict(self) -> dict[str, Any]:
        """The summary as plain values (NaN kept: callers write it with finite_json)."""
        return asdict(self)


class _Robot:
    """One run: the world, the endpoint, the newest valid command, the counters."""

    def __init__(self, opts: RobotOptions, endpoint: Endpoint) -> None:
        self.opts, self.endpoint = opts, endpoint
        ground, friction = scenario_world(opts.world)
        plant = with_floor_friction(build_plant(opts.control_period, opts.robot, ground), friction)
        self.n = check_motor_order(plant.motor_names)
        qpos0 = standing_qpos(plant)
        sim = SimOptions(control_period=opts.control_period, noise=opts.noise, seed=opts.faults.seed)
        self.world = World(plant, qpos0, sim, False, 1, depth_camera=False)  # LowState_ carries no depth
        self.world.on_ground(ground)
        self.dt = self.world.dt
        self.start_xy = qpos0[:2].copy()
        self.summary = RobotSummary()
        self.command: MotorCommand | None = None
        self.command_time = -math.inf  # s of simulated time when the command arrived
        self.fresh = False  # lockstep: a valid command arrived since the last clock was written
        self.state: Any = None  # the last intact LowState_ written
        self.clock = topic_writer(endpoint, CLOCK_TOPIC, Clock_) if opts.lockstep else None
        self.tick = Clock_()  # lockstep: the clock of this tick
        self.link = Link(opts.faults, self.dt, corrupted)
        zero = np.zeros(self.n)
        self.damping = MotorCommand(q=zero, dq=zero, kp=zero, kd=np.full(self.n, opts.damping_kd), tau=zero)
        self.estimates = topic_reader(endpoint, ESTIMATE_TOPIC, Estimate_, depth=256)
        self.score = EstimateScore()
        m, meta = plant.model, {"process": "robot", "robot": opts.robot, "period": self.dt, "motors": plant.motor_names}
        self.recorder = Recorder(opts.record, robot_widths(self.n, m.nq, m.nv), meta) if opts.record else None

    def publish(self, k: int) -> None:
        """Observe tick ``k`` (the fall test) and write its state."""
        why = self.world.observe(k)
        if why is not None and not self.summary.fell:
            self.summary.fell, self.summary.fall_time, self.summary.fall_reason = True, k * self.dt, why
        d, contacts = self.world.d, self.world.contacts
        assert contacts is not None
        self.score.truth(k, d.qpos, d.qvel, contacts.touching)
        self.link.take(k, lowstate_from_frame(self.world.sense(k), k, self.opts.mode_machine))
        for state, intact in self.link.release(k):
            self.endpoint.writer.write(state)
            self.summary.states_published += 1
            if intact:
                self.state = state

    def write_clock(self, k: int) -> None:
        """Lockstep: write the clock of tick ``k`` (:mod:`gaitshift.dds.lockstep`); its command is awaited."""
        assert self.clock is not None
        self.tick = Clock_(tick=k % 2**32, state_tick=self.state.tick)
        self.clock.write(self.tick)
        self.fresh = False

    def resend(self) -> None:
        """Lockstep: write the newest intact state and this tick's clock again (no command came)."""
        self.endpoint.writer.write(self.state)
        self.summary.states_published += 1
        assert self.clock is not None
        self.clock.write(self.tick)

    def receive(self, t: float) -> None:
        """Take every LowCmd_ received: count it, keep the newest valid one (arrival at sim time ``t``)."""
        s = self.summary
        for msg in self.endpoint.take():
            s.packets_received += 1
            try:
                self.command = command_from_lowcmd(msg, self.n)
            except InputError as e:
                s.packets_dropped += 1
                s.crc_rejects += e.field.endswith(".crc")
                s.last_error = str(e)
                continue
            self.command_time, self.fresh = t, True
        self.take_estimates()

    def take_estimates(self) -> None:
        """Score every Estimate_ received (:mod:`gaitshift.dds.scoring`)."""
        for msg in self.estimates.take(N=256):
            if isinstance(msg, Estimate_):
                self.score.add(msg)

    def act(self, k: int) -> None:
        """Apply the command of tick ``k`` (damping when none is recent) and step the physics; held in the
        gantry (real time, no valid command yet), only count the tick."""
        t, s = k * self.dt, self.summary
        s.ticks, s.sim_time = k + 1, (k + 1) * self.dt
        if self.opts.gantry and not self.opts.lockstep and self.command is None:
            s.held_ticks += 1
            if self.recorder is not None:
                self.record(k, None, 0)
            return
        if self.command is not None and t - self.command_time <= self.opts.damping_after:
            cmd, s.commands_applied, applied = self.command, s.commands_applied + 1, 1
        else:
            cmd, s.damping_ticks, applied = self.damping, s.damping_ticks + 1, 2
        if self.recorder is not None:
            self.record(k, cmd, applied)
        self.world.apply(cmd, k)
        self.world.step()

    def record(self, k: int, cmd: MotorCommand | None, applied: int) -> None:
        """Tick ``k``'s row of the recording: the truth before the step, the command applied (None: held in
        the gantry, nothing applied, the command's columns zero)."""
        assert self.recorder is not None and self.world.contacts is not None
        d, c = self.world.d, self.world.contacts
        row = {"qpos": d.qpos, "qvel": d.qvel, "touching": c.touching, "grf": c.grf.ravel()}
        cmd_row = command_values(cmd) if cmd is not None else {}
        self.recorder.add(t=k * self.dt, tick=k, applied=applied, **row, **cmd_row)


def scenario_world(world: str | None) -> tuple[Terrain, float | None]:
    """The ground and the floor friction of the world of scenario ``world`` (None: flat, the model's)."""
    if world is None:
        return FLAT, None
    try:
        sc = load_scenario(world)
    except InputError as e:
        field = "--world" if e.field == "scenario" else f"--world {world}: {e.field}"
        raise InputError(field, e.value, e.allowed) from None
    sim = getattr(sc, "sim", None)
    return world_ground(sc) or FLAT, getattr(sim, "friction", None)


def corrupted(state: Any) -> Any:
    """A copy of the ``LowState_`` with its CRC off by one (the link's corruption)."""
    bad = copy.copy(state)
    bad.crc = (int(state.crc) + 1) & 0xFFFFFFFF
    return bad


def _wait_for_command(robot: _Robot, k: int, stop: StopSignals) -> bool:
    """Lockstep: block until a valid command arrives for the clock of tick ``k`` (the state and the clock
    written again every ``resend`` s); False when stopped by a signal first."""
    while not stop.why:
        robot.receive(k * robot.dt)
        if robot.fresh:
            return True
        if not robot.endpoint.wait(robot.opts.resend):
            robot.resend()
    return False


def _pace(wall0: float, k: int, dt: float, summary: RobotSummary) -> float:
    """Real time: sleep until tick ``k`` is due at ``wall0 + k dt``; the start time, moved on by a late tick's
    lateness (no burst of catch-up ticks: a robot's ticks come a period apart, and a brain that acts on each
    state's arrival needs them to); a tick over a period late is counted."""
    late = time.perf_counter() - (wall0 + k * dt)
    if late < 0:
        time.sleep(-late)
        return wall0
    summary.late_ticks += late > dt
    return wall0 + late


def run_robot(opts: RobotOptions, endpoint: Endpoint | None = None) -> RobotSummary:
    """Run the robot process (module docstring) until ``opts.duration`` or SIGINT/SIGTERM."""
    endpoint = endpoint or open_endpoint(opts.domain, opts.iface, "robot")
    robot = _Robot(opts, endpoint)
    stop = StopSignals()
    n_ticks = math.inf if opts.duration is None else round(opts.duration / robot.dt)
    set_priority(opts.rt_priority, "--rt-priority")
    wall0 = start = time.perf_counter()
    k = 0
    try:
        while k < n_ticks and not stop.why:
            if not opts.lockstep:
                wall0 = _pace(wall0, k, robot.dt, robot.summary)
            robot.publish(k)
            if opts.lockstep and robot.state is not None:
                robot.write_clock(k)
                if not _wait_for_command(robot, k, stop):
                    break
            robot.receive(k * robot.dt)
            robot.act(k)
            k += 1
    finally:
        stop.restore()
        s = robot.summary
        s.stopped_by = stop.why or "duration"
        s.wall_time = time.perf_counter() - start
        s.distance = float(np.linalg.norm(robot.world.d.qpos[:2] - robot.start_xy))
        c = robot.link.counts
        s.link_dropped, s.link_corrupted = c.dropped, c.corrupted
        s.link_delay_ticks_mean, s.link_delay_ticks_max = c.delay_ticks_mean, c.delay_ticks_max
        robot.take_estimates()
        score = robot.score.summary()
        for f in fields(ScoreSummary):
            setattr(s, f.name, getattr(score, f.name))
        if robot.recorder is not None:
            robot.recorder.save()
    return robot.summary
