"""Closed loop: the controller (:class:`~gaitshift.control.controller.Controller`) hosted by the
simulated world (:class:`~gaitshift.sim.world.World`).

Every control tick (= physics step, 2 ms by default)::

    world.observe(k)         the truth for the metrics; stop at a fall (pelvis below 60 % of its initial
                             height above the ground, or any non-sole geom touching it)
    frame = world.sense(k)   SensorFrame: what the robot reports (the truth barrier: plain arrays)
    cmd = ctrl.tick(frame)   the brain: estimator, driver, scheduler, step feedback, whole-body QP
    world.apply(cmd, k)      the motors' law through the latency pipe, and the push
    hooks, log, video        (they read the world and the controller's record, never write)
    world.step()

The run starts in the pose the controller's plan starts in (``ctrl.initial_qpos()``) and ends when
the plan ends or the robot falls, with the metrics of :mod:`gaitshift.sim.metrics`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.control.controller import Controller
from gaitshift.control.drivers import PlanDriver
from gaitshift.control.feedback import CaptureSettings
from gaitshift.control.reference import SwingSettings
from gaitshift.control.schedule import ScheduleSettings
from gaitshift.control.settings import ControllerSettings, floor_height
from gaitshift.control.wbc_data import Gains
from gaitshift.errors import InputError, check_flag
from gaitshift.models.terrain import Terrain
from gaitshift.robots.config import RobotConfig
from gaitshift.robots.model import robot_model
from gaitshift.scenario.sim_settings import check_friction
from gaitshift.sim.bumps import Bump, check_bumps
from gaitshift.sim.estimation_metrics import sensing_metrics
from gaitshift.sim.latency import CommandDelay
from gaitshift.sim.leg_clearance import LegClearance
from gaitshift.sim.log import EstimationLog, FootholdLog, PerceptionLog, ScanLog, TickLog
from gaitshift.sim.metrics import summarize
from gaitshift.sim.perception_metrics import perception_metrics
from gaitshift.sim.perturb import check_com_offset, check_joint_vel_noise, check_mass_scale, check_motor_strength
from gaitshift.sim.plant import Plant, build_plant
from gaitshift.sim.pushes import Push
from gaitshift.sim.result import SimResult
from gaitshift.sim.video import VIDEO_SIZE, VideoRecorder, check_video, close_viewer, open_viewer, video_overlay
from gaitshift.sim.world import World, with_floor_friction
from gaitshift.trajectory.contract import Trajectory

#: called after the control of every tick: (tick index, plan time s, the plant's MjData); a hook with an
#: ``attach(controller)`` method is handed the run's controller first (the browser view draws its map)
TickHook = Callable[[int, float, Any], None]
#: the SimOptions that configure the controller (the rest configure the world)
CONTROLLER_KEYS = (
    "gains",
    "schedule",
    "capture",
    "swing",
    "settle",
    "state",
    "noise",
    "noise_scale",
    "estimator",
    "assumed_friction",
    "contact",
    "replan",
)


@dataclass(frozen=True)
class SimOptions:
    """Options of a closed-loop run.

    Attributes:
        control_period: control period = physics time step, s.
        gains: whole-body QP weights and gains; None: the defaults with the robot YAML's ``control``
            values (:func:`gaitshift.control.wbc_data.gains_for`).
        schedule: foot state machine timing; capture: step feedback; swing: swing-path additions.
        settle: s of standing before the plan starts.
        pushes: pushes on the pelvis (plan time).
        video: MP4 path, or None; video_fps: its frame rate, Hz; video_size: (width, height), pixels.
        viewer: open MuJoCo's passive viewer (needs a display).
        state: what the controller sees, "estimated" (sensors + estimator) or "oracle" (the truth);
            None (the default): "estimated" when the robot's model carries the IMU, else "oracle".
        noise, noise_scale: sensor noise profile ("none", "typical", "rl-peer") and its factor.
        latency: loop latency, ticks (sensing + actuation); predict_latency: compensate it.
        friction: the floor's friction coefficient (None: the model's).
        assumed_friction: the friction the controller assumes at start (None: the conservative default).
        estimator: base filter of the state estimator; seed: seed of every random draw of the run.
        mass_scale: factor on the masses and inertias of the simulated robot only; the controller keeps
            the nominal model (:mod:`gaitshift.sim.perturb`).
        com_offset: (3,) m, the simulated base's centre of mass moved in the base frame (the truth only).
        motor_strength: factor on the simulated motors' torque and torque limit (the truth only).
        joint_vel_noise: extra uniform noise on the joint velocities the drivers report, rad/s
            half-width (:mod:`gaitshift.sim.perturb`; estimated state only).
        bumps: boxes on the floor of the simulated world only (:mod:`gaitshift.sim.bumps`; ignored
            when ``simulate`` is given a ``plant``).
        contact: the controller's contact sensing: ``"force"`` (the robot has sole force sensors) or
            ``"torque"`` (it has none: the world reports no foot force and the controller finds the
            sole forces from the motors' torques, :mod:`gaitshift.control.estimation.torque_contact`);
            None (the default): what the robot YAML's ``sensors.foot_force`` says the real robot has
            (:func:`gaitshift.control.settings.contact_source`): torques for every shipped robot, whose
            real soles carry no force sensors (docs/robots.md, "On the estimate": what holds on torques).
        replan: where a plan driver re-plans (:mod:`gaitshift.control.replanner`): ``"inline"`` (the
            default: in the tick, deterministic) or ``"thread"`` / ``"process"`` (a background worker, as
            on a robot: the run then depends on the worker's timing).
        known_floor: True: the controller is told that a world without terrain and bumps is the flat
            floor at z = 0 (:attr:`gaitshift.control.settings.ControllerSettings.floor`, docs/estimation.md
            "A known floor"); False (the default): it is not.

    The actuation delay is ``latency``: one setting for the sensing-to-actuation delay of the loop
    (:mod:`gaitshift.sim.latency`), not a second one.
    """

    control_period: float = 0.002
    gains: Gains | None = None
    schedule: ScheduleSettings = field(default_factory=ScheduleSettings)
    capture: CaptureSettings = field(default_factory=CaptureSettings)
    swing: SwingSettings = field(default_factory=SwingSettings)
    settle: float = 0.0
    pushes: tuple[Push, ...] = ()
    video: str | None = None
    video_fps: int = 30
    video_size: tuple[int, int] = VIDEO_SIZE
    viewer: bool = False
    # sensing (gaitshift.sim.world) and the controller state (gaitshift.control.state)
    state: str | None = None
    noise: str = "typical"
    noise_scale: float = 1.0
    latency: int = 0
    predict_latency: bool = True
    friction: float | None = None
    assumed_friction: float | None = None
    estimator: str = "inekf"
    seed: int = 0
    mass_scale: float = 1.0
    com_offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    motor_strength: float = 1.0
    joint_vel_noise: float = 0.0
    bumps: tuple[Bump, ...] = ()
    contact: str | None = None
    replan: str = "inline"
    known_floor: bool = False

    def __post_init__(self) -> None:
        self.controller_settings()  # the controller's keys, checked
        check_friction("friction", self.friction)
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise InputError("seed", self.seed, "an integer >= 0")
        CommandDelay.check(self.latency)
        check_video(self.video_size, self.video_fps)
        check_mass_scale(self.mass_scale)
        object.__setattr__(self, "com_offset", check_com_offset(self.com_offset))  # a list from YAML: a tuple
        check_motor_strength(self.motor_strength)
        check_joint_vel_noise(self.joint_vel_noise)
        check_bumps(self.bumps)
        check_flag("known_floor", self.known_floor)

    def controller_settings(self) -> ControllerSettings:
        """The controller's part of the options (the latency compensated when ``predict_latency``)."""
        given = {k: getattr(self, k) for k in CONTROLLER_KEYS}
        latency = self.latency if self.predict_latency and not isinstance(self.latency, bool) else 0
        return ControllerSettings(**given, latency=latency if isinstance(latency, int) else 0)


class _Run:
    """The state of one closed-loop run: the controller, the world, the log."""

    def __init__(self, ctrl: Controller, world: World, opts: SimOptions, hooks: Sequence[TickHook] = ()) -> None:
        self.ctrl, self.world, self.opts, self.hooks = ctrl, world, opts, tuple(hooks)
        self.dt = world.dt
        self.video: VideoRecorder | None = None
        self.n_ticks = round(ctrl.duration_bound / self.dt) + 1
        self.clearance = LegClearance.of(world.plant)
        self.log = TickLog(min(self.n_ticks, round(60.0 / self.dt)), world.plant.model)
        self.est_log = EstimationLog()
        self.map_log = PerceptionLog()
        self.scan_log = ScanLog()
        self.foothold_log = FootholdLog()
        self.sense_hooks: tuple[TickHook, ...] = ()
        for hook in self.hooks:
            attach = getattr(hook, "attach", None)
            if attach is not None:
                attach(ctrl)

    def execute(self) -> SimResult:
        """Run the ticks until the plan ends or the robot falls; return the result with its metrics."""
        ctrl, world, opts, d = self.ctrl, self.world, self.opts, self.world.d
        video = None
        if opts.video:
            plant = world.plant
            overlay = video_overlay(ctrl.trajectory, plant.robot.sole_size)
            track, height = plant.pelvis_body, plant.robot.com_height
            video = self.video = VideoRecorder(
                world.physics, opts.video, opts.video_fps, opts.video_size, track, height, overlay
            )
        viewer = open_viewer(world.physics, d) if opts.viewer else None
        fell, fall_time, reason = False, math.nan, ""
        n_done = self.n_ticks
        wall0 = time.perf_counter()
        for k in range(self.n_ticks):
            t = k * self.dt
            tp = ctrl.plan_time(t)
            if ctrl.finished(t):
                n_done = k
                break
            why = world.observe(k)
            if why is not None:
                fell, fall_time, reason, n_done = True, tp, why, k
                break
            frame = world.sense(k)
            for hook in self.sense_hooks:
                hook(k, tp, d)
            cmd = ctrl.tick(frame)
            push = world.apply(cmd, k)
            for hook in self.hooks:
                hook(k, tp, d)
            self._record(k, tp, push)
            if video is not None:
                video.capture(t, d, d.subtree_com[0].copy())
            if viewer is not None:
                viewer.sync()
            world.step()
        wall = time.perf_counter() - wall0 - (video.wall if video is not None else 0.0)  # control + physics only
        if video is not None:
            video.close()
        if viewer is not None:
            close_viewer(viewer)
        return self._result(n_done, wall, fell, fall_time, reason)

    def _record(self, k: int, tp: float, push: np.ndarray) -> None:
        """Log tick ``k``: the world's truth and the controller's record."""
        world, rec, d = self.world, self.ctrl.record, self.world.d
        assert rec is not None and world.contacts is not None
        frames = [world.plant.sole_frame(d, s) for s in (0, 1)]
        feet = np.array([centre for centre, _ in frames])
        clear = self.clearance.read(d, frames)
        self.log.record(
            k, tp, rec.plan_index, d, world.applied, world.contacts, rec.reference, rec.info, rec.shift,
            rec.contact_ref, feet, push, clear,
        )  # fmt: skip
        if rec.estimate is not None:
            self.est_log.record(rec.estimate)
        self.foothold_log.record(tp, self.ctrl.trajectory)
        if self.ctrl.perceiver is not None:
            self.map_log.record(tp, self.ctrl.perceiver.map, feet[:, :2])
            self.scan_log.record(tp, self.ctrl.perceiver)

    def _result(self, n_done: int, wall: float, fell: bool, fall_time: float, reason: str) -> SimResult:
        arrays = {**self.log.arrays(n_done), **self.est_log.arrays(n_done), **self.map_log.arrays(n_done)}
        arrays |= self.scan_log.arrays() | self.foothold_log.arrays()
        plan = self.ctrl.whole_plan()
        result = SimResult(arrays, fell, fall_time, reason, self._meta(n_done, wall), {}, plan)
        result.metrics = summarize(result, plan, self.world.plant.torque_limit)
        result.metrics.update(sensing_metrics(result.arrays, self.ctrl.source))
        frames = self.ctrl.perceiver.frames if self.ctrl.perceiver is not None else 0
        sole = (float(self.world.plant.robot.sole_size[0]), float(self.world.plant.robot.sole_size[1]))
        result.metrics.update(perception_metrics(result.arrays, frames, self.world.ground, sole, self.dt))
        stopped = getattr(self.ctrl.driver, "stopped", None)  # the perceived driver's stop before an edge
        if stopped is not None and "perception" in result.metrics:
            result.metrics["perception"]["stopped"] = stopped
        return result

    def _meta(self, n_done: int, wall: float) -> dict[str, Any]:
        sim_time = n_done * self.dt
        plant, ctrl, opts = self.world.plant, self.ctrl, self.opts
        return {
            "robot": plant.robot.source or plant.robot.name,
            "control_period": self.dt,
            "integrator": "implicitfast",
            "plan_meta": ctrl.trajectory.meta,
            "wall_time_s": wall,
            "sim_time_s": sim_time,
            "real_time_factor": sim_time / wall if wall > 0 else math.nan,
            "torque_limit": plant.torque_limit.tolist(),
            "pelvis_height0": self.world.pelvis0,
            "pushes": [asdict(p) for p in opts.pushes],
            "bumps": [asdict(b) for b in opts.bumps],
            "mass_scale": opts.mass_scale,
            "com_offset": list(opts.com_offset),
            "motor_strength": opts.motor_strength,
            "joint_vel_noise": opts.joint_vel_noise,
            "settle": opts.settle,
            "replans": ctrl.driver.replans if ctrl.driver is not None else 0,
            "sensing": {
                key: getattr(opts, key)
                for key in ("state", "noise", "noise_scale", "latency", "predict_latency", "friction", "seed")
            }
            | {"estimator": opts.estimator, "assumed_friction_final": ctrl.state.mu},
        }


def simulate(
    traj: Trajectory,
    opts: SimOptions | None = None,
    plant: Plant | None = None,
    driver: PlanDriver | None = None,
    hooks: Sequence[TickHook] = (),
    robot: str | Path | RobotConfig = "g1",
    sense_hooks: Sequence[TickHook] = (),
    ground: Terrain | None = None,
) -> SimResult:
    """Run the plan ``traj`` closed-loop on ``robot`` (built-in name, YAML or config; ignored when
    ``plant`` is given; the plant gets ``ground``, else the plan's terrain, ``traj.meta["terrain"]``:
    a planner not told the terrain plans on flat ground the world does not have) and return the
    logged result (see module docstring). To simulate a scenario, use
    :func:`gaitshift.sim.scenario_run.simulate_scenario`, which picks the driver and applies its
    ``sim:`` block.

    With a ``driver`` (a :class:`~gaitshift.control.drivers.PlanDriver`: online VHIP and locomotion
    plans), the plan is the driver's, regenerated from the measured CoM at every planning instant.
    ``hooks`` are called after the control of every tick with (tick, plan time s, the plant's MjData):
    a live session (:mod:`gaitshift.sim.teleop`) reads its keys and paces the run there.
    ``sense_hooks`` are called right after sensing, before the controller ticks (tests of the truth
    barrier).
    """
    opts = opts or SimOptions()
    if driver is not None:
        traj = driver.trajectory
    terrain = ground if ground is not None else Terrain.from_list(traj.meta.get("terrain"))  # the world's ground
    plant = with_floor_friction(plant or build_plant(opts.control_period, robot, terrain, opts.bumps), opts.friction)
    settings = opts.controller_settings()
    floor = floor_height(opts.known_floor, terrain.flat, opts.bumps)
    if floor is not None:
        settings = replace(settings, floor=floor)
    ctrl = Controller(traj, robot_model(plant.robot, plant.dt), settings, driver)
    n_ticks = round(ctrl.duration_bound / plant.dt) + 1
    world = World(plant, ctrl.initial_qpos(), opts, ctrl.source == "oracle", n_ticks)
    world.on_ground(terrain)
    ctrl.calibrate(world.still_gyro())
    run = _Run(ctrl, world, opts, hooks)
    run.sense_hooks = tuple(sense_hooks)
    try:
        return run.execute()
    except BaseException:
        if run.video is not None:
            run.video.discard()  # no partial MP4
        raise
