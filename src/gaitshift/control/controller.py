"""The robot's brain: one object, built once, ticked once per control period.

.. code-block:: text

    SensorFrame -> state (estimator | oracle, latency prediction)     gaitshift.control.state
                -> plan driver (re-plan from the measured CoM)        gaitshift.control.drivers
                -> foot scheduler (early / late touchdown)            gaitshift.control.schedule
                -> step feedback (capture point, plan shift)          gaitshift.control.feedback
                -> tick reference, friction belief, whole-body QP     gaitshift.control.reference, wbc
                -> MotorCommand

Everything the robot's computer runs lives here; nothing in it reads a world. A world (the
simulation, the Unitree protocol, a user's own simulator) hosts it::

    ctrl = Controller.from_scenario("g1-walk")
    qpos = ctrl.initial_qpos()                   # the world starts the robot there, at rest
    while not ctrl.finished(t):
        cmd = ctrl.tick(frame)                   # frame: SensorFrame at time t
        ...                                      # apply tau + kp (q - q_meas) + kd (dq - dq_meas)

After each tick :attr:`Controller.record` holds what the controller did (plan sample, reference, QP
result, plan shift, its state estimate): a host may log it, never feed it back.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import partial
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from gaitshift.control.cop_room import CopRoom
from gaitshift.control.drivers import PlanDriver, prepare
from gaitshift.control.estimation.noise import noise_profile
from gaitshift.control.feedback import PlanShift, SwingContext
from gaitshift.control.frames import MotorCommand, SensorFrame
from gaitshift.control.initial_pose import initial_qpos
from gaitshift.control.perception import Perceiver
from gaitshift.control.plan_history import PlanHistory
from gaitshift.control.plan_samples import PlanSamples
from gaitshift.control.reference import tick_reference
from gaitshift.control.replanner import replanner
from gaitshift.control.schedule import FootScheduler
from gaitshift.control.settings import ControllerSettings, contact_source, floor_height
from gaitshift.control.state import MAX_BRIDGE, ControllerState, EstimateRecord, StateView
from gaitshift.control.step_limits import StepLimits
from gaitshift.control.wbc import WholeBodyController
from gaitshift.control.wbc_data import TickInfo, TickReference, gains_for
from gaitshift.errors import InputError, check_flag, number_in
from gaitshift.robots.config import RobotConfig
from gaitshift.robots.model import RobotModel, check_period, robot_model
from gaitshift.trajectory.contract import OPEN_END, Trajectory
from gaitshift.trajectory.window import first_index, index_at

__all__ = ["Controller", "TickRecord"]


@dataclass(frozen=True)
class TickRecord:
    """What the controller did at one tick.

    Attributes:
        t: plan time, s; plan_index: the plan sample tracked (the run's: in :meth:`Controller.whole_plan`).
        reference: the tick reference; info: the QP's result; shift: (3,) m plan shift of the step
        feedback; contact_ref: (2,) bool the plan's contact flags; estimate: the estimator's output
        (None for a model without an IMU).
    """

    t: float
    plan_index: int
    reference: TickReference
    info: TickInfo
    shift: np.ndarray
    contact_ref: np.ndarray
    estimate: EstimateRecord | None


class Controller:
    """The robot's brain (module docstring).

    Args:
        plan: the plan to execute (with a ``driver``: the driver's plan as known at start).
        robot: the controller's robot model (:func:`gaitshift.robots.model.robot_model`).
        settings: the controller's settings.
        driver: re-plans a streaming plan from the measured CoM (:mod:`gaitshift.control.drivers`), or None.
    """

    def __init__(
        self,
        plan: Trajectory,
        robot: RobotModel,
        settings: ControllerSettings | None = None,
        driver: PlanDriver | None = None,
    ) -> None:
        s = settings or ControllerSettings()
        perceives = getattr(driver, "perceives", False)  # footholds from the map (inline, or copies handed over)
        if driver is not None:
            plan = driver.trajectory
            if not driver.step_feedback:
                s = replace(s, capture=replace(s.capture, gain=0.0, anchor=False))
        # where the driver re-plans (inline, or a background worker: then the host's driver is its proxy)
        self.replan = None if driver is None else replanner(driver, s.replan, robot.robot.sole_size[0])
        driver = None if self.replan is None else self.replan.driver
        self.settings, self.robot, self.driver, self.traj = s, robot, driver, plan
        self.dt = robot.dt
        self.plan = PlanSamples.from_trajectory(plan, robot.robot.sole_size[0])
        self.history = PlanHistory(plan)
        self.q0 = initial_qpos(robot, plan.com_pos[0], plan.foot_pos[0], self.plan.yaw[0])
        d = mujoco.MjData(robot.model)
        d.qpos[:] = self.q0
        mujoco.mj_forward(robot.model, d)
        self.wbc = WholeBodyController(robot, self.q0, s.gains if s.gains is not None else gains_for(robot.robot))
        self.sched = FootScheduler(plan, self.plan, s.schedule, robot.weight)
        height = float(plan.meta.get("height", plan.com_pos[0, 2]))
        limits = StepLimits.from_plant(robot, height, s.capture.reach_fraction, s.capture.tandem_clearance)
        half = np.asarray(plan.meta.get("foot_size", (0.0, 0.0)), float) / 2
        sole = (float(half[0]), float(half[1]))
        room = CopRoom.from_plant(robot, d, sole) if s.capture.cop_room else sole
        omega = math.sqrt(plan.gravity / height)
        self.shift = PlanShift(s.capture, omega, limits, room, robot.mass * plan.gravity)
        self.last_info = TickInfo()  # the last solve: the stance soles' CoP (commanded_cop)
        self.source = s.state or "estimated"
        profile = noise_profile(s.noise).scaled(float(s.noise_scale))
        oracle = self.source == "oracle"
        self.state = ControllerState(
            robot,
            self.q0,
            profile,
            oracle,
            s.estimator,
            s.latency,
            s.assumed_friction,
            contact_source(s.contact, robot.robot),
            s.floor,
            s.position_tau,
            s.stance_point,
        )
        self.record: TickRecord | None = None
        cam = robot.robot.sensors.depth_camera
        self.perceiver = None if cam is None else Perceiver(robot.model, cam)  # the elevation map
        if perceives:
            if self.perceiver is None:
                raise InputError("terrain", "perceived", f"known or blind ({robot.robot.name} has no depth camera)")
            self.replan.watch(self.perceiver.map)  # type: ignore[union-attr]

    @classmethod
    def from_scenario(
        cls,
        scenario: Any,
        robot: str | Path | RobotConfig | None = None,
        state: str | None = None,
        known_floor: bool | None = None,
        **settings: Any,
    ) -> Controller:
        """The controller of ``scenario`` (a built-in name, a YAML path or a loaded scenario) on
        ``robot`` (default: the scenario's, else g1), acting on ``state`` ("estimated", "oracle";
        None: the scenario's ``sim: state``, else estimated: every robot has an IMU, its YAML's
        ``sensors.imu``).
        ``settings`` are :class:`ControllerSettings` keys, and ``control_period`` (s, 0.002). With
        ``known_floor`` (None: the scenario's ``sim: known_floor``, else False) a scenario without
        ``terrain`` and ``bumps`` tells the controller that the robot is on the flat floor (``floor`` = 0,
        docs/estimation.md "A known floor")."""
        period = settings.pop("control_period", 0.002)
        sc, cfg, driver, plan = prepare(scenario, robot, check_period(period))
        model = robot_model(cfg, period)
        sim = sc.sim.given() if hasattr(sc, "sim") else {}
        given = {k: v for k, v in sim.items() if k in _SCENARIO_KEYS}
        known = check_flag("known_floor", sim.get("known_floor", False) if known_floor is None else known_floor)
        floor = floor_height(known, not getattr(sc, "terrain", ()), sim.get("bumps"))
        if floor is not None:
            given["floor"] = floor
        if state is not None:
            given["state"] = state
        cs = ControllerSettings.of(**(given | settings))
        return cls(plan, model, cs, driver)

    # --- what a host needs -------------------------------------------------------------------

    @property
    def period(self) -> float:
        """The control period, s: tick once per period."""
        return self.dt

    @property
    def motor_names(self) -> tuple[str, ...]:
        """The motors, in the order of every per-motor array of frames and commands."""
        return self.robot.motor_names

    @property
    def imu_site(self) -> str | None:
        """The MJCF site the IMU readings refer to (None: the model has none; oracle only)."""
        return self.robot.imu_site

    @property
    def foot_bodies(self) -> tuple[str, str]:
        """The (left, right) foot bodies of the model: where a world measures foot force."""
        left, right = self.robot.robot.sole_bodies
        return (left, right)

    @property
    def mjcf_path(self) -> Path:
        """The robot's model file."""
        return Path(self.robot.robot.mjcf)

    @property
    def trajectory(self) -> Trajectory:
        """The plan as known now (a driver extends and re-plans it; a live driver's is a window of the run
        from a second back, :mod:`gaitshift.trajectory.window`): a new object after each re-plan."""
        return self.traj

    def whole_plan(self) -> Trajectory:
        """The run's plan as tracked so far (:class:`~gaitshift.control.plan_history.PlanHistory`; put
        together on each call)."""
        return self.history.whole()

    def initial_qpos(self) -> np.ndarray:
        """The full configuration (nq,) in which the plan starts, at rest: the world starts there."""
        return self.q0.copy()

    def plan_time(self, t: float) -> float:
        """Plan time, s, at time ``t`` s of the controller's clock (after the ``settle`` s of standing)."""
        return max(0.0, t - self.settings.settle)

    def finished(self, t: float) -> bool:
        """The plan has ended at time ``t`` s (half a period past its last sample), and it is the run's last:
        a live plan's look-ahead (``meta["open_end"]``) that a re-plan off the tick has not yet continued
        is not the end of the run (its last sample is held until the new plan comes)."""
        over = self.plan_time(t) > float(self.traj.t[-1]) + 0.5 * self.dt
        return over and not self.traj.meta.get(OPEN_END, False)

    @property
    def duration_bound(self) -> float:
        """An upper bound of the run's length, s (settle included)."""
        end = self.driver.duration_bound if self.driver is not None else float(self.traj.t[-1])
        return end + self.settings.settle

    # --- live input ----------------------------------------------------------------------------

    def command(self, vx: float, vy: float, yaw_rate: float) -> None:
        """A live velocity command (m/s in the heading frame, rad/s), from the next planning instant."""
        self._live("command").command(vx, vy, yaw_rate)

    def goto(self, x: float, y: float, yaw: float = 0.0) -> None:
        """Walk to (x, y) m and turn to ``yaw`` rad (world frame), then stand."""
        self._live("goto").gen.goto(x, y, yaw)

    def stop(self) -> None:
        """Ramp down and stand."""
        self._live("stop").stop()

    def _live(self, what: str) -> Any:
        if self.driver is None or not hasattr(self.driver, "gen") or not hasattr(self.driver, "command"):
            raise InputError(what, "this plan", "a live-command (locomotion) scenario")
        return self.driver

    def calibrate(self, still_gyro: np.ndarray, period: float | None = None) -> None:
        """Gyro readings (N, 3) rad/s taken while the robot stood still before the first tick, one every
        ``period`` s (None: the control period): the estimator's gyro-bias prior
        (:mod:`gaitshift.control.estimation.calibration`)."""
        g = np.asarray(still_gyro, dtype=float)
        if g.ndim != 2 or g.shape[1] != 3 or len(g) < 2 or not np.all(np.isfinite(g)):
            raise InputError("still_gyro", g.shape, "an (N >= 2, 3) array of finite rates, rad/s")
        if period is not None:
            number_in("period", period, (1e-6, 60.0), "s")
        self.state.calibrate(g, self.period if period is None else float(period))

    # --- the tick ------------------------------------------------------------------------------

    def tick(self, frame: SensorFrame, age: int = 0) -> MotorCommand:
        """One control period: the frame in, the motor command out (module docstring). ``age``: ticks between
        the frame's readings (taken at ``frame.t``) and this tick, for a host whose link delays them; the
        controller acts at ``frame.t + age`` periods, on the state predicted across the commands sent since
        (:mod:`gaitshift.control.prediction`). A frame of the last one's ``t`` (no new readings) is not
        measured again. The tick's time is taken to the nearest period: a live plan's samples, and the
        instants it re-plans at, lie on that grid (a host on a wall clock need not round)."""
        self._check(frame)
        if isinstance(age, bool) or not isinstance(age, int | np.integer) or not 0 <= age <= MAX_BRIDGE:
            raise InputError("age", age, f"an integer number of ticks in [0, {MAX_BRIDGE}]")
        tp = self.plan_time(round(frame.t / self.dt + int(age)) * self.dt)  # on the period's grid
        view = self.state.observe(frame, self._planned_contact(tp), int(age))
        if frame.depth_points is not None and self.perceiver is not None:
            self.perceiver.frame(frame.t, frame.depth_points, view.data)
        i = self._plan_index(tp, view)
        tau, ref, info = self._control(tp, i, view)
        self.state.sent(info.qdd)
        at = i + first_index(self.traj)  # the run's sample
        rec = TickRecord(tp, at, ref, info, self.shift.shift.copy(), self.traj.contact[i], self.state.record)
        self.record = rec
        return MotorCommand.torque(tau)

    def measure(self, frame: SensorFrame) -> None:
        """Readings that a newer frame overtook before a tick (a link that brought two at once): the estimator
        takes them, in the order taken, before the tick on the newest; no command."""
        self._check(frame)
        self.state.measure(frame, self._planned_contact(self.plan_time(frame.t)))

    def _planned_contact(self, tp: float) -> np.ndarray:
        """The plan's contact flags (2,) bool at plan time ``tp`` s (its last sample's past the end)."""
        return np.asarray(self.traj.contact[index_at(self.traj, tp)])

    def _check(self, frame: SensorFrame) -> None:
        """:class:`InputError` naming the first per-motor field of ``frame`` of the wrong size or not finite."""
        n = self.robot.model.nu
        for name in ("q", "dq", "tau_est"):
            a = getattr(frame, name)
            if np.shape(a) != (n,) or not np.isfinite(a).all():
                raise InputError(f"SensorFrame.{name}", np.shape(a), f"{n} finite numbers (one per motor)")

    def _plan_index(self, tp: float, view: StateView) -> int:
        """Plan sample at plan time ``tp``, after re-planning from the measured CoM when it is due."""
        if self.replan is not None:
            c = view.data
            for new, samples in self.replan.step(tp, c.subtree_com[0].copy(), c.subtree_linvel[0]):
                self.traj, self.plan = new, samples
                self.sched.retarget(new, samples)
                self.history.adopt(new, round(tp / new.dt))
        return index_at(self.traj, tp)

    def _control(self, tp: float, i: int, view: StateView) -> tuple[np.ndarray, TickReference, TickInfo]:
        """Schedule, feedback, reference, QP on the view: the torques (nu,) N m, reference, QP result."""
        sched, shift, traj, c = self.sched, self.shift, self.traj, view.data
        com = c.subtree_com[0].copy()
        was_swing = ~sched.stance
        if tp > 0 or self.settings.settle == 0:
            sched.update(tp, i, view.touching)
        shift.land(was_swing & sched.stance)
        measured, planned = self._footholds(view)
        if self.settings.capture.anchor and not self.state.oracle:  # the truth has no drift to absorb
            shift.anchor_on(sched.stance & ~view.slip, measured, planned)
        shift.blend(self.dt)
        progress = np.array([sched.swing_progress(tp, s) for s in (0, 1)])
        left = np.maximum(sched.swing_end - tp, 0.0), float(self.plan.heading[i])
        stance_left = np.where(sched.stance, np.maximum(sched.lift_at - tp, 0.0), 0.0)
        load = partial(self._load_factor, tp, i) if shift.cop is not None else None  # only the CoP room uses it
        ctx = SwingContext(planned, measured, *left, stance_left, load, self.last_info.cop_offset)
        shift.correct_swings(sched.stance, progress, com, c.subtree_linvel[0], traj.com_pos[i], traj.com_vel[i], ctx)
        pos_std = 0.0 if self.plan.terrain.flat else self.state.position_std()
        ref = tick_reference(traj, self.plan, i, tp, sched, shift, self.settings.swing, pos_std)
        self.wbc.gains = self.state.friction(self.wbc.gains, view, traj.contact[i])
        tau, info = self.wbc.compute(c, ref)
        self.last_info = info
        return tau, ref, info

    def _load_factor(self, tp: float, i: int, tau: float) -> float:
        """The plan's mean vertical force over ``[tp, tp + tau]`` in units of the weight (plan sample ``i``
        at time ``tp``): ``1 + (zd(tp + tau) - zd(tp)) / (g tau)``, the CoM's impulse balance
        (:mod:`gaitshift.control.cop_room`)."""
        traj = self.traj
        j = min(int(np.searchsorted(traj.t, tp + tau)), len(traj.t) - 1)
        return 1.0 + float(traj.com_vel[j, 2] - traj.com_vel[i, 2]) / (traj.gravity * tau)

    def _footholds(self, view: StateView) -> tuple[np.ndarray, np.ndarray]:
        """Sole positions (2, 3) m as the controller sees them, and the plan's footholds (2, 3) m of the
        stances the scheduler is at (the plan's sole positions at each foot's last planned touchdown)."""
        measured = np.array([self.robot.sole_frame(view.data, s)[0] for s in (0, 1)])
        planned = np.array([self.traj.foot_pos[self.sched.landing_sample(s), s] for s in (0, 1)])
        return measured, planned


#: the keys of a scenario's ``sim:`` block that configure the controller (the rest configure the world)
_SCENARIO_KEYS = ("state", "noise", "noise_scale", "assumed_friction", "latency", "contact")
