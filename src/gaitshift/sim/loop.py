"""Closed loop: a planned :class:`~gaitshift.trajectory.contract.Trajectory` executed on a simulated robot.

Every control tick (= physics step, 2 ms by default):

1. read the truth for the metrics (``mj_forward`` + ``mj_subtreeVel``, foot contacts of :mod:`gaitshift.sim.contacts`);
   stop at a fall (pelvis below 60 % of its initial height, both above the plan's terrain, or any non-sole geom
   touching the ground); sense (:mod:`gaitshift.sim.sensing`): sensors, state estimator (or the truth with
   ``state="oracle"``), latency prediction, the controller's OWN ``MjData``: steps 2-5 read only that view (the truth
   barrier);
2. online VHIP plans: re-plan at each planning instant from the measured CoM
   (:mod:`gaitshift.control.online_driver`);
3. update the foot state machine (contact schedule of the plan, with early/late touchdown from the
   measured contacts, :mod:`gaitshift.control.schedule`);
4. step-level feedback of TV-LIPM plans: capture-point foothold corrections and the plan shift
   (:mod:`gaitshift.control.feedback`; off for online plans, whose footholds do that job);
5. build the tick reference (:mod:`gaitshift.control.reference`), solve the whole-body QP
   (:mod:`gaitshift.control.wbc`), apply the torques and the pushes (:mod:`gaitshift.sim.pushes`);
6. log (:mod:`gaitshift.sim.log`), render (:mod:`gaitshift.sim.video`) and step the physics.

The run starts in the standing pose on the plan's first footholds (:mod:`gaitshift.sim.initial_pose`)
and ends with the metrics of :mod:`gaitshift.sim.metrics`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field, replace
from functools import partial
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from gaitshift.control.cop_room import CopRoom
from gaitshift.control.drivers import PlanDriver
from gaitshift.control.feedback import CaptureSettings, PlanShift, SwingContext
from gaitshift.control.plan_samples import PlanSamples
from gaitshift.control.reference import SwingSettings, tick_reference
from gaitshift.control.schedule import FootScheduler, ScheduleSettings
from gaitshift.control.step_limits import StepLimits
from gaitshift.control.wbc import WholeBodyController
from gaitshift.control.wbc_data import Gains, TickInfo, gains_for
from gaitshift.models.terrain import Terrain
from gaitshift.robots.config import RobotConfig
from gaitshift.sim.bumps import Bump, check_bumps
from gaitshift.sim.contacts import ContactSensor, fall_reason
from gaitshift.sim.estimation_metrics import sensing_metrics
from gaitshift.sim.initial_pose import initial_qpos
from gaitshift.sim.leg_clearance import LegClearance
from gaitshift.sim.log import TickLog
from gaitshift.sim.metrics import summarize
from gaitshift.sim.perturb import check_joint_vel_noise, check_mass_scale, scaled_masses
from gaitshift.sim.plant import Plant, build_plant
from gaitshift.sim.pushes import Push, push_forces
from gaitshift.sim.result import SimResult
from gaitshift.sim.sensing import ControllerView, Sensing, check_sensing_options, with_floor_friction
from gaitshift.sim.video import VIDEO_SIZE, VideoRecorder, check_video, close_viewer, open_viewer, video_overlay
from gaitshift.trajectory.contract import Trajectory

#: called after the control of every tick: (tick index, plan time s, the plant's MjData)
TickHook = Callable[[int, float, Any], None]


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
        joint_vel_noise: extra uniform noise on the joint velocities the drivers report, rad/s
            half-width (:mod:`gaitshift.sim.perturb`; estimated state only).
        bumps: boxes on the floor of the simulated world only (:mod:`gaitshift.sim.bumps`; ignored
            when ``simulate`` is given a ``plant``).

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
    # sensing and the truth barrier (gaitshift.sim.sensing)
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
    joint_vel_noise: float = 0.0
    bumps: tuple[Bump, ...] = ()

    def __post_init__(self) -> None:
        check_sensing_options(self)
        check_video(self.video_size, self.video_fps)
        check_mass_scale(self.mass_scale)
        check_joint_vel_noise(self.joint_vel_noise)
        check_bumps(self.bumps)


class _Run:
    """The state of one closed-loop run: plant data, controller, scheduler, feedback, log."""

    def __init__(
        self,
        traj: Trajectory,
        opts: SimOptions,
        plant: Plant,
        replanner: PlanDriver | None,
        hooks: Sequence[TickHook] = (),
    ) -> None:
        self.traj, self.opts, self.plant, self.replanner = traj, opts, plant, replanner
        self.hooks = tuple(hooks)
        self.video: VideoRecorder | None = None
        self.d = mujoco.MjData(plant.model)
        self.dt = plant.dt
        self.plan = PlanSamples.from_trajectory(traj, plant.robot.sole_size[0])
        q0 = initial_qpos(plant, traj.com_pos[0], traj.foot_pos[0], self.plan.yaw[0])
        self.d.qpos[:] = q0
        mujoco.mj_forward(plant.model, self.d)
        self.ground = Terrain.from_list(traj.meta.get("terrain"))  # pelvis heights are above the ground
        self.pelvis0 = float(q0[2] - self.ground.height(q0[0]))
        gains = opts.gains if opts.gains is not None else gains_for(plant.robot)
        self.ctrl = WholeBodyController(plant, q0, gains)
        self.sched = FootScheduler(traj, self.plan, opts.schedule, plant.mass * 9.81)
        height = float(traj.meta.get("height", traj.com_pos[0, 2]))
        limits = StepLimits.from_plant(plant, height, opts.capture.reach_fraction, opts.capture.tandem_clearance)
        half = np.asarray(traj.meta.get("foot_size", (0.0, 0.0)), float) / 2
        sole = (float(half[0]), float(half[1]))
        room = CopRoom.from_plant(plant, self.d, sole) if opts.capture.cop_room else sole
        omega = math.sqrt(traj.gravity / height)
        self.shift = PlanShift(opts.capture, omega, limits, room, plant.mass * traj.gravity)
        self.last_info = TickInfo()  # the controller's last solve: the stance soles' CoP (commanded_cop)
        self.sensor = ContactSensor(plant)
        self.clearance = LegClearance.of(plant)
        end = replanner.duration_bound if replanner is not None else float(traj.t[-1])
        self.n_ticks = round((end + opts.settle) / self.dt) + 1
        self.push = push_forces(opts.pushes, opts.settle, self.dt, self.n_ticks)
        self.log = TickLog(min(self.n_ticks, round(60.0 / self.dt)), plant.model)
        self.sensing = Sensing(plant, opts, q0)
        self.sense_hooks: tuple[TickHook, ...] = ()
        self.physics = scaled_masses(plant.model, opts.mass_scale)  # the truth; the controller: nominal

    def plan_index(self, tp: float, view: ControllerView) -> int:
        """Plan sample at plan time ``tp``, after re-planning from the measured CoM when it is due."""
        if self.replanner is not None:
            c = view.data
            new = self.replanner.maybe_replan(tp, c.subtree_com[0].copy(), c.subtree_linvel[0])
            if new is not None:
                self.traj, self.plan = new, PlanSamples.from_trajectory(new, self.plant.robot.sole_size[0])
                self.sched.retarget(new, self.plan)
        return min(round(tp / self.traj.dt), len(self.traj) - 1)

    def control(self, k: int, tp: float, i: int, view: ControllerView) -> tuple[Any, ...]:
        """Schedule, feedback, reference, QP on the controller's view; send the command and the push
        of tick ``k``; return what the log needs."""
        sched, shift, traj, d, c = self.sched, self.shift, self.traj, self.d, view.data
        com = c.subtree_com[0].copy()
        was_swing = ~sched.stance
        if tp > 0 or self.opts.settle == 0:
            sched.update(tp, i, view.touching)
        shift.land(was_swing & sched.stance)
        measured, planned = self.footholds(view)
        if self.opts.capture.anchor and not self.sensing.oracle:  # the truth has no drift to absorb
            shift.anchor_on(sched.stance & ~view.slip, measured, planned)
        shift.blend(self.dt)
        progress = np.array([sched.swing_progress(tp, s) for s in (0, 1)])
        left = np.maximum(sched.swing_end - tp, 0.0), float(self.plan.heading[i])
        stance_left = np.where(sched.stance, np.maximum(sched.lift_at - tp, 0.0), 0.0)
        load = partial(self.load_factor, tp, i) if shift.cop is not None else None  # only the CoP room uses it
        ctx = SwingContext(planned, measured, *left, stance_left, load, self.last_info.cop_offset)
        shift.correct_swings(sched.stance, progress, com, c.subtree_linvel[0], traj.com_pos[i], traj.com_vel[i], ctx)
        pos_std = 0.0 if self.plan.terrain.flat else self.sensing.position_std()
        ref = tick_reference(traj, self.plan, i, tp, sched, shift, self.opts.swing, pos_std)
        self.ctrl.gains = self.sensing.friction(self.ctrl.gains, view)
        tau, info = self.ctrl.compute(c, ref)
        self.last_info = info
        tau = self.sensing.actuate(d, tau, info.qdd)  # the only write to the plant, with the push
        push = self.push[k] if k < len(self.push) else np.zeros(3)
        d.xfrc_applied[self.plant.pelvis_body, :3] = push
        return tau, ref, info, shift.shift.copy(), traj.contact[i], push

    def load_factor(self, tp: float, i: int, tau: float) -> float:
        """The plan's mean vertical force over ``[tp, tp + tau]`` in units of the weight (plan sample ``i``
        at time ``tp``): ``1 + (zd(tp + tau) - zd(tp)) / (g tau)``, the CoM's impulse balance
        (:mod:`gaitshift.control.cop_room`)."""
        traj = self.traj
        j = min(int(np.searchsorted(traj.t, tp + tau)), len(traj.t) - 1)
        return 1.0 + float(traj.com_vel[j, 2] - traj.com_vel[i, 2]) / (traj.gravity * tau)

    def footholds(self, view: ControllerView) -> tuple[np.ndarray, np.ndarray]:
        """Sole positions (2, 3) m as the controller sees them, and the plan's footholds (2, 3) m of the
        stances the scheduler is at (the plan's sole positions at each foot's last planned touchdown)."""
        measured = np.array([self.plant.sole_frame(view.data, s)[0] for s in (0, 1)])
        last = len(self.traj) - 1
        j = [min(round(self.sched.swing_end[s] / self.traj.dt), last) for s in (0, 1)]
        planned = np.array([self.traj.foot_pos[j[s], s] for s in (0, 1)])
        return measured, planned

    def execute(self) -> SimResult:
        """Run the ticks until the plan ends or the robot falls; return the result with its metrics."""
        m, d, opts = self.physics, self.d, self.opts
        video = None
        if opts.video:
            overlay = video_overlay(self.traj, self.plant.robot.sole_size)
            track, height = self.plant.pelvis_body, self.plant.robot.com_height
            video = self.video = VideoRecorder(m, opts.video, opts.video_fps, opts.video_size, track, height, overlay)
        viewer = open_viewer(m, d) if opts.viewer else None
        fell, fall_time, reason = False, math.nan, ""
        n_done = self.n_ticks
        wall0 = time.perf_counter()
        for k in range(self.n_ticks):
            t = k * self.dt
            tp = max(0.0, t - opts.settle)
            if tp > float(self.traj.t[-1]) + 0.5 * self.dt:
                n_done = k
                break
            if k > 0:
                self.sensing.latch(d)
            mujoco.mj_forward(m, d)
            mujoco.mj_subtreeVel(m, d)
            contacts = self.sensor.read(d)  # truth: the metrics and the fall test
            why = fall_reason(contacts, float(d.qpos[2] - self.ground.height(d.qpos[0])), self.pelvis0)
            if why is not None:
                fell, fall_time, reason, n_done = True, tp, why, k
                break
            planned = self.traj.contact[min(round(tp / self.traj.dt), len(self.traj) - 1)]  # the plan, not the plant
            view = self.sensing.observe(k, d, contacts, planned)
            for hook in self.sense_hooks:
                hook(k, tp, d)
            i = self.plan_index(tp, view)
            tau, ref, info, shift, contact_ref, push = self.control(k, tp, i, view)
            for hook in self.hooks:
                hook(k, tp, d)
            frames = [self.plant.sole_frame(d, s) for s in (0, 1)]
            feet = np.array([centre for centre, _ in frames])
            clear = self.clearance.read(d, frames)
            self.log.record(k, tp, i, d, tau, contacts, ref, info, shift, contact_ref, feet, push, clear)
            if video is not None:
                video.capture(t, d, d.subtree_com[0].copy())
            if viewer is not None:
                viewer.sync()
            mujoco.mj_step(m, d)
        wall = time.perf_counter() - wall0 - (video.wall if video is not None else 0.0)  # control + physics only
        if video is not None:
            video.close()
        if viewer is not None:
            close_viewer(viewer)
        arrays = {**self.log.arrays(n_done), **self.sensing.log.arrays(n_done)}
        result = SimResult(arrays, fell, fall_time, reason, self._meta(n_done, wall), {})
        result.metrics = summarize(result, self.traj, self.plant.torque_limit)
        result.metrics.update(sensing_metrics(result.arrays, self.sensing.source))
        return result

    def _meta(self, n_done: int, wall: float) -> dict[str, Any]:
        sim_time = n_done * self.dt
        return {
            "robot": self.plant.robot.source or self.plant.robot.name,
            "control_period": self.dt,
            "integrator": "implicitfast",
            "plan_meta": self.traj.meta,
            "wall_time_s": wall,
            "sim_time_s": sim_time,
            "real_time_factor": sim_time / wall if wall > 0 else math.nan,
            "torque_limit": self.plant.torque_limit.tolist(),
            "pelvis_height0": self.pelvis0,
            "pushes": [asdict(p) for p in self.opts.pushes],
            "bumps": [asdict(b) for b in self.opts.bumps],
            "mass_scale": self.opts.mass_scale,
            "joint_vel_noise": self.opts.joint_vel_noise,
            "settle": self.opts.settle,
            "replans": self.replanner.replans if self.replanner is not None else 0,
            "sensing": {
                key: getattr(self.opts, key)
                for key in ("state", "noise", "noise_scale", "latency", "predict_latency", "friction", "seed")
            }
            | {"estimator": self.opts.estimator, "assumed_friction_final": self.sensing.mu},
        }


def simulate(
    traj: Trajectory,
    opts: SimOptions | None = None,
    plant: Plant | None = None,
    replanner: PlanDriver | None = None,
    hooks: Sequence[TickHook] = (),
    robot: str | Path | RobotConfig = "g1",
    sense_hooks: Sequence[TickHook] = (),
) -> SimResult:
    """Run ``traj`` closed-loop on ``robot`` (built-in name, YAML or config; ignored when ``plant`` is
    given; the plant gets the plan's terrain, ``traj.meta["terrain"]``) and return the logged result
    (see module docstring).

    With a ``replanner`` (a :class:`~gaitshift.control.drivers.PlanDriver`: online VHIP and locomotion
    plans), the plan is regenerated from the measured CoM at every
    planning instant and the capture-point shift is not used (the generator's footholds do that job).
    ``hooks`` are called after the control of every tick with (tick, plan time s, the plant's MjData):
    a live session (:mod:`gaitshift.sim.teleop`) reads its keys and paces the run there.
    ``sense_hooks`` are called right after sensing, before the controller side runs (tests of the
    truth barrier, :mod:`gaitshift.sim.sensing`).
    """
    opts = opts or SimOptions()
    if replanner is not None:
        traj = replanner.trajectory
        if not replanner.step_feedback:
            opts = replace(opts, capture=replace(opts.capture, gain=0.0, anchor=False))
    terrain = Terrain.from_list(traj.meta.get("terrain"))  # the plan's ground, built into the scene
    plant = with_floor_friction(plant or build_plant(opts.control_period, robot, terrain, opts.bumps), opts.friction)
    run = _Run(traj, opts, plant, replanner, hooks)
    run.sense_hooks = tuple(sense_hooks)
    try:
        return run.execute()
    except BaseException:
        if run.video is not None:
            run.video.discard()  # no partial MP4
        raise
