"""The controller's state: what it knows at one tick, from a :class:`~gaitshift.control.frames.SensorFrame` only.

Per tick::

    x_hat    = estimator.step(frame, planned)        StateEstimator (inekf by default); planned: the plan's
                                                     contact flags at this tick (the fused contact)
    x_ctrl   = x_hat (estimated) | frame.oracle      one state for controller, driver and step feedback
    x_ctrl   = predict(x_ctrl, pending commands)     latency and age compensation (control.prediction)
    data.qpos, qvel = x_ctrl; forward_terms         the controller's OWN MjData (contacts off)

The controller, the driver and the step feedback read only :class:`StateView`: the controller's
``MjData`` (CoM = ``subtree_com[0]``, its velocity = ``subtree_linvel[0]``, frames and Jacobians all
from the one state), the contact flags (for the estimate: the force trigger's stance flags, or a
landing the fused contact sees; for the oracle: the frame's oracle contact) and the slip flags. The
contact flags are what the foot scheduler's touch-down events read. A walking foot grazes the floor
with a few newtons about 15 ticks before the plan's touch-down, and a foot the controller still takes
for a swinging one is driven along its swing while the floor holds it. The force trigger alone took
those touch-downs a median 16 ticks late (g1-walk, seed 0, contact from torques); a landing (the sole
back at the ground level after it left the floor, the other sole standing:
:mod:`gaitshift.control.estimation.contact_fusion`) takes them 2 ticks early (docs/estimation.md,
"Touch-downs from a landing"). The estimator also runs when the controller acts on
the oracle (its output unused), so every run reports how well it tracks. The first tick is the start
state at rest, both feet down on a level floor: the plan's start pose with the joints its encoders measure
and the base tilt that puts the soles level (:func:`~gaitshift.control.initial_pose.sensed_start`); the
estimator starts from it.

Latency: the controller acts on the state predicted for the tick its command acts at
(:mod:`gaitshift.control.prediction`): ``latency`` ticks after the frame, plus the frame's ``age`` (ticks
between its readings and the tick, for a host whose link delays them). A frame repeated with the same ``t``
(a tick that brought no new readings) is not measured again: the estimate of its first tick is predicted
one tick further.

Missing states: a frame ``g > 1`` periods after the last one (a state the link lost or corrupted, over
DDS) first steps the estimator through the ``g - 1`` ticks it did not see, on the new frame's readings held
(zero-order hold; each joint angle moved back along its reported velocity, ``q - j dt dq`` for the tick
``j`` periods before the frame), so that the filter integrates the IMU over the time that passed and the
torque contact's window keeps one state per period. Up to :data:`MAX_BRIDGE` ticks: a longer silence is
the link's stale-state fault, not the estimator's business.

Friction: the controller starts from ``assumed_friction`` and, on the estimated state, multiplies it by
:data:`FRICTION_DROP` at every detected slip onset of a sole in the plan's stance, down to
:data:`FRICTION_MIN`; it never raises it again within a run. A sole the plan swings is one the
controller does not load, so its slide says nothing of the floor: a running foot that lands before its
planned touchdown slides in on its impact, and a swinging sole wrongly taken for a stance one (contact
from the motors' torques) moves with its leg. Counted, those onsets took the G1 tour on torque contact
from 0.45 to 0.10 within 0.55 s and it fell at 12.33 s (docs/estimation.md). On the oracle it is kept
fixed: on the G1 tour (floor friction 1.0) brief sole slides at running impacts lowered it to 0.23 and
worsened the tracking.
"""

from __future__ import annotations

import copy
import math
import time
from dataclasses import dataclass, replace
from typing import Any

import mujoco
import numpy as np

from gaitshift.control.estimation import GyroCalibration, StateEstimator
from gaitshift.control.estimation.contact import noise_thresholds
from gaitshift.control.estimation.inekf import InvariantEKF
from gaitshift.control.estimation.joints import JointVelocityFilter
from gaitshift.control.estimation.noise import NoiseProfile
from gaitshift.control.estimation.torque_contact import AccelerationWindow, TorqueContact, second_difference_variance
from gaitshift.control.estimation.tuning import FilterTuning
from gaitshift.control.estimation.types import FootForces, ImuReading, JointReading
from gaitshift.control.frames import SensorFrame
from gaitshift.control.initial_pose import sensed_start
from gaitshift.control.position_filter import PositionFilter
from gaitshift.control.prediction import LatencyPredictor
from gaitshift.errors import InputError
from gaitshift.robots.model import RobotModel, forward_terms

#: friction coefficient the controller assumes unless told: conservative against rubber soles on a dry
#: floor (0.6-1.0) and the simulated contact (1.0); the QP's pyramid |fx|, |fy| <= mu fz lets the
#: diagonal reach sqrt(2) mu. 0.35 costs the oracle G1 runs 0.2 cm of CoM RMS (docs/estimation.md)
DEFAULT_ASSUMED_FRICTION = 0.45
FRICTION_DROP = 0.8
FRICTION_MIN = 0.1
#: slip of a stance sole on the oracle: low-passed horizontal speed (tau s) above this, m/s
SLIP_SPEED, SLIP_TAU = 0.2, 0.03
#: how well the start tilt is known, rad: the run starts at rest, standing on a level floor in a known
#: pose (the estimator's reset state); the prior lets the filter separate the accelerometer's turn-on
#: bias from the tilt while the robot stands (a level floor is known to about 1 mrad)
START_TILT_STD = 1e-3
#: samples of the moving average of the sole forces; the thresholds follow from the force noise
#: (gaitshift.control.estimation.contact.noise_thresholds: 4 and 1.5 std of the averaged noise)
CONTACT_WINDOW = 2
#: std of the torque-derived sole force (eq. (2) of gaitshift.control.estimation.torque_contact) against
#: the true normal force, a fraction of the weight per sample, as the contact thresholds assume it: the
#: stance error measured on g1-walk on the estimate is 0.015 against the window's mean force, 0.05 against
#: the force of the tick (docs/estimation.md, "Contact without foot force")
TORQUE_FORCE_STD = 0.02
#: half width n (ticks) of the window over which the torque-derived sole forces are taken: joint
#: accelerations from second differences of the estimated joint angles over 2 n ticks (g1-walk on the
#: estimate, stance error std against the true mean force over the window: n = 2: 5.3 %, n = 5: 1.5 %,
#: n = 10: 1.0 % of the weight; the difference of two estimated velocities: 18-20 %). Closed loop on
#: g1-walk-run-walk (seed 0): n = 5 holds (contact accuracy 95.5 %), n = 3 fell at 7.63 s
TORQUE_WINDOW = 5
#: the torque window widens with the encoders' noise (:func:`torque_window`) until its part of the sole force
#: is at most this many times TORQUE_FORCE_STD (G1, rl-peer noise: n = 10; docs/estimation.md, "Heavy sensor noise")
TORQUE_NOISE_SHARE = 3.0
TORQUE_WINDOW_MAX = 20
#: the largest std of the torques' centre of pressure (per sample, at half the weight; a share of the sole's
#: length) with which the estimator takes it as the stance point: ``typical`` noise gives 0.8 % on the G1
#: (1.4 mm), ``rl-peer`` 5-6 % (about 1 cm), and with it g1-walk's contact accuracy fell from 0.924 to 0.867
#: and its velocity RMSE rose from 0.028 to 0.035 m/s (seed 0)
COP_STD_MAX = 0.02
#: most ticks a missing stretch of states is bridged over (module docstring), 20 ms at 2 ms
MAX_BRIDGE = 10


@dataclass(frozen=True)
class StateView:
    """What the controller acts on at one tick.

    Attributes:
        data: the controller's own ``MjData`` at that state (:func:`~gaitshift.robots.model.forward_terms`
            and ``mj_subtreeVel`` done: no accelerations, constraint forces or sensors).
        touching: (2,) bool stance flags; slip: (2,) bool stance soles sliding.
    """

    data: Any
    touching: np.ndarray
    slip: np.ndarray


@dataclass(frozen=True)
class EstimateRecord:
    """The estimator's output at one tick (used by the controller or not): ``qpos`` (nq), ``qvel``
    (nv), ``contact`` (the fused contact), ``stance`` (the force-confirmed stance the scheduler gets),
    ``slip`` (2, bool), ``com``, ``com_vel`` (3), ``mu`` (friction assumed), ``tick_us`` (estimator
    cost, µs; 0 at the first tick, the known start state)."""

    qpos: np.ndarray
    qvel: np.ndarray
    contact: np.ndarray
    stance: np.ndarray
    slip: np.ndarray
    com: np.ndarray
    com_vel: np.ndarray
    mu: float
    tick_us: float


class OracleSlip:
    """Slip on the oracle: a sole touching the floor whose low-passed horizontal speed exceeds
    :data:`SLIP_SPEED` (the estimator's rule, on the true sole velocity)."""

    def __init__(self, dt: float) -> None:
        self.alpha = 1.0 - np.exp(-dt / SLIP_TAU)
        self.lp = np.zeros((2, 2))

    def update(self, sole_velocity: np.ndarray, touching: np.ndarray) -> np.ndarray:
        for s in (0, 1):
            self.lp[s] = self.lp[s] + self.alpha * (sole_velocity[s] - self.lp[s]) if touching[s] else 0.0
        slip: np.ndarray = touching & (np.sum(self.lp**2, axis=1) > SLIP_SPEED**2)
        return slip


class ControllerState:
    """Estimator, oracle path, latency prediction, friction belief and the controller's ``MjData``
    (module docstring).

    Args:
        robot: the controller's robot model.
        qpos0: the known start state (nq,), at rest.
        profile: the sensor noise profile the estimator is tuned to (already scaled).
        oracle: act on the frame's oracle state instead of the estimate.
        estimator: base filter name; latency: ticks between a frame and its command acting.
        assumed_friction: the friction assumed at start (None: :data:`DEFAULT_ASSUMED_FRICTION`).
        contact: where the sole forces of the contact detector come from: ``"force"`` (the frame's
            ``foot_force``) or ``"torque"`` (the motors' torques,
            :mod:`~gaitshift.control.estimation.torque_contact`).
        floor: the height, m, of a flat floor known under the robot (a measurement of the estimator,
            :mod:`~gaitshift.control.estimation.floor`); None: unknown.
        position_tau: s, the time constant of the horizontal position the controller acts on
            (:mod:`~gaitshift.control.position_filter`; 0: the estimate's as it is).
        stance_point: ``"cop"``: with contact from the torques, the estimator's stance points at the soles'
            centres of pressure; ``"centre"``: at the soles' centres (:attr:`ControllerSettings.stance_point`).
    """

    def __init__(
        self,
        robot: RobotModel,
        qpos0: np.ndarray,
        profile: NoiseProfile,
        oracle: bool,
        estimator: str,
        latency: int,
        assumed_friction: float | None,
        contact: str = "torque",
        floor: float | None = None,
        position_tau: float = 0.0,
        stance_point: str = "centre",
    ) -> None:
        m = robot.model
        self.stance_point = stance_point
        self.position = PositionFilter(position_tau)  # what the controller acts on: eq. (1) there
        self.robot, self.oracle = robot, oracle
        self.qpos0 = np.asarray(qpos0, float).copy()
        self.cmodel = copy.copy(m)
        self.cmodel.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
        self.cdata = mujoco.MjData(m)
        self.predictor = LatencyPredictor(self.cmodel, latency, MAX_BRIDGE)
        self.mu = float(assumed_friction if assumed_friction is not None else DEFAULT_ASSUMED_FRICTION)
        self._slip_prev = np.zeros(2, bool)
        self.oracle_slip = OracleSlip(robot.dt)
        self.estimator: StateEstimator | None = None
        self.torque_contact: TorqueContact | None = None
        self._window: AccelerationWindow | None = None
        # at rest on both feet, until the window fills
        self._force0 = np.full(2, robot.weight / 2)
        self.record: EstimateRecord | None = None
        self.ticks = 0
        self._last_t = 0.0  # s, the time of the last frame
        # the last tick's estimated state (nq,), (nv,) before the latency prediction (module docstring)
        self._measured = (self.qpos0, np.zeros(m.nv))
        # the state the last tick acted on, before the prediction: q (nq,), v (nv,), touching, slip (2,)
        self._acted = (self.qpos0, np.zeros(m.nv), np.ones(2, bool), np.zeros(2, bool))
        tuning = FilterTuning.from_profile(profile, robot.dt, init_tilt_std=START_TILT_STD)
        force_std = profile.force
        if contact == "torque":
            self.torque_contact = TorqueContact(robot)
            n, force_std, cop_std = torque_window(self.torque_contact, self.qpos0, tuning)
            self._window = AccelerationWindow(n, robot.dt)
            if cop_std > COP_STD_MAX * float(robot.robot.sole_size[0]):
                self.stance_point = "centre"  # the CoP of these sensors is mostly noise
        on, off = noise_thresholds(force_std, CONTACT_WINDOW)
        self.estimator = StateEstimator.from_robot(
            robot.robot,
            robot.dt,
            tuning=tuning,
            filter=estimator,
            imu_site=robot.imu_site,
            contact_on=on,
            contact_off=off,
            debounce=1,
            contact_window=CONTACT_WINDOW,
        )
        if isinstance(self.estimator.filter, InvariantEKF):
            self.estimator.filter.floor = floor
        self.gyro_bias_walk = profile.gyro_bias_walk
        self._calibration: GyroCalibration | None = None
        self.start = self.qpos0  # the start state the estimator began from (the first frame's)

    def calibrate(self, still_gyro: np.ndarray, period: float) -> None:
        """The estimator's gyro-bias prior at its first tick: readings (N, 3) rad/s, one every ``period`` s,
        of the robot standing still (:mod:`gaitshift.control.estimation.calibration`)."""
        if self.estimator is None:
            return
        self._calibration = GyroCalibration.from_samples(still_gyro, period, self.gyro_bias_walk)

    def observe(self, frame: SensorFrame, planned: np.ndarray, age: int = 0) -> StateView:
        """The tick's view from ``frame``, ``age`` ticks old (with the plan's contact flags ``planned`` (2,));
        a frame of the last one's ``t`` is not measured again (module docstring, "Latency")."""
        if not self.ticks or frame.t != self._last_t:
            self.measure(frame, planned)
        return self._view(*self._acted, age)

    def measure(self, frame: SensorFrame, planned: np.ndarray) -> None:
        """Take ``frame``'s readings (the estimator's step; with the plan's contact flags ``planned`` (2,)):
        the state the next view acts on. Every frame, also one that a newer frame overtook before the tick."""
        first, self.ticks = self.ticks == 0, self.ticks + 1
        if self.oracle and frame.oracle is None:
            raise InputError("SensorFrame.oracle", None, "the world's state: this controller acts on the oracle")
        since, self._last_t = self._last_t, frame.t
        if self.estimator is None:
            self._acted = self._oracle(frame)
            return
        if first:  # at rest, both feet down: the start state from the encoders on a level floor
            self.start = sensed_start(self.robot, self.qpos0, frame.q)
            self.estimator.reset(self.start, np.zeros(self.robot.model.nv), (True, True), self._calibration)
            q_est, v_est = self.start, np.zeros(self.robot.model.nv)
            touch_est, slip_est, com, com_vel, cost = np.ones(2, bool), np.zeros(2, bool), None, None, 0.0
            fused, landing = touch_est, np.zeros(2, bool)
            self.position.reset(q_est)
        else:
            imu = ImuReading(gyro=frame.imu_gyro, accel=frame.imu_acc)
            self._bridge(frame, imu, planned, since)
            joints = JointReading(q=frame.q, qd=frame.dq)
            forces = self._sole_forces(frame)
            t0 = time.perf_counter()
            s = self.estimator.step(imu, joints, forces, planned)
            cost = 1e6 * (time.perf_counter() - t0)
            q_est, v_est, touch_est, slip_est, com, com_vel = s.qpos(), s.qvel(), s.stance, s.slip, s.com, s.com_vel
            fused, landing = s.contact, self.estimator.landing
        self._measured = (q_est, v_est)
        if self.oracle:
            self._acted = self._oracle(frame)
        else:
            q_act = q_est.copy()
            q_act[:2] = self.position.step(q_est, v_est, frame.t - since)
            self._acted = (q_act, v_est, touch_est | landing, slip_est)
        if com is None or com_vel is None:  # the first tick: the start state's, as the controller's data holds it
            c = self._view(q_est, v_est, touch_est, slip_est, 0).data
            com, com_vel = c.subtree_com[0].copy(), c.subtree_linvel[0].copy()
        self.record = EstimateRecord(q_est, v_est, fused, touch_est, slip_est, com, com_vel, self.mu, cost)

    def _bridge(self, frame: SensorFrame, imu: ImuReading, planned: np.ndarray, since: float) -> None:
        """Step the estimator through the ticks between the last frame (at ``since`` s) and ``frame`` that no
        frame came for (module docstring, "Missing states"); the torque window takes each of their states."""
        assert self.estimator is not None
        dt = self.robot.dt
        gap = min(round((frame.t - since) / dt), MAX_BRIDGE + 1)
        for j in range(gap - 1, 0, -1):
            joints = JointReading(q=frame.q - j * dt * frame.dq, qd=frame.dq)
            s = self.estimator.step(imu, joints, self._sole_forces(frame), planned)
            self._measured = (s.qpos(), s.qvel())

    def _sole_forces(self, frame: SensorFrame) -> FootForces:
        """The sole normal forces (2,) N the contact detector reads: the frame's foot force, or eq. (2)
        of :mod:`~gaitshift.control.estimation.torque_contact` on the last tick's state with the soles'
        centres of pressure (eq. (4)), the filter's stance points."""
        if self.torque_contact is not None:
            return self._torque_forces(frame.tau_est)
        if frame.foot_force is None:
            allowed = "the sole normal forces, N (or a controller with contact='torque')"
            raise InputError("SensorFrame.foot_force", None, allowed)
        return FootForces(normal=frame.foot_force)

    def _torque_forces(self, tau_est: np.ndarray) -> FootForces:
        """Eqs. (2) and (4) of :mod:`~gaitshift.control.estimation.torque_contact` at the centre of the last
        ``2 n + 1`` ticks (:class:`~gaitshift.control.estimation.torque_contact.AccelerationWindow`)."""
        window, contact = self._window, self.torque_contact
        assert window is not None and contact is not None
        window.push(*self._measured, tau_est)
        if not window.full:
            return FootForces(normal=self._force0.copy())
        d = window.centre_data(self.cmodel)
        normal, cop = contact.sole_loads(d, window.mean_torque(), window.acceleration())
        return FootForces(normal=normal, cop=cop if self.stance_point == "cop" else None)

    def sent(self, qdd: np.ndarray | None) -> None:
        """The command just sent planned the accelerations ``qdd`` (nv,) (None: the QP failed)."""
        self.predictor.sent(qdd)

    def _oracle(self, frame: SensorFrame) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        o = frame.oracle
        assert o is not None
        touching = np.asarray(o.contact, bool)
        return o.qpos.copy(), o.qvel.copy(), touching, self.oracle_slip.update(o.sole_velocity, touching)

    def _view(self, q: np.ndarray, v: np.ndarray, touching: np.ndarray, slip: np.ndarray, age: int) -> StateView:
        q, v = self.predictor.predict(q, v, age)
        c = self.cdata
        c.qpos[:], c.qvel[:] = q, v
        forward_terms(self.cmodel, c)
        mujoco.mj_subtreeVel(self.cmodel, c)
        return StateView(data=c, touching=np.asarray(touching, bool), slip=np.asarray(slip, bool))

    def friction(self, gains: Any, view: StateView, planned: np.ndarray) -> Any:
        """The gains with the friction assumed now: lowered at each slip onset of a sole in the plan's
        stance (``planned`` (2,) bool, the plan's contact flags of this tick), on the estimated state
        only (module docstring)."""
        onset = view.slip & ~self._slip_prev & np.asarray(planned, bool)
        self._slip_prev = view.slip.copy()
        if onset.any() and not self.oracle:
            self.mu = max(FRICTION_MIN, FRICTION_DROP * self.mu)
        return gains if gains.mu == self.mu else _with_mu(gains, self.mu)

    def position_std(self) -> float:
        """Std (m) of the controller's base position along x: the estimator's (the InEKF's world-frame
        covariance, error order R, v, p: row 6), 0 on the oracle or for a filter without a covariance."""
        filt = self.estimator.filter if self.estimator is not None and not self.oracle else None
        world_cov = getattr(filt, "world_covariance", None)
        if world_cov is None:
            return 0.0
        return float(np.sqrt(max(world_cov()[6, 6], 0.0)))


def torque_window(contact: TorqueContact, qpos0: np.ndarray, tuning: FilterTuning) -> tuple[int, float, float]:
    """The torque window's half width n (ticks), the std of its sole force (fraction of the weight, per
    sample) and of its centre of pressure (m, per sample, at half the weight) for the sensors of ``tuning``:
    the smallest n from :data:`TORQUE_WINDOW` to :data:`TORQUE_WINDOW_MAX` whose encoder-noise part (eq. (3)
    of :mod:`~gaitshift.control.estimation.torque_contact`, at the pose ``qpos0``) is at most
    :data:`TORQUE_NOISE_SHARE` times :data:`TORQUE_FORCE_STD`; the force's std is the larger of the two."""
    robot, d = contact.robot, mujoco.MjData(contact.robot.model)
    d.qpos[:] = qpos0
    mujoco.mj_forward(robot.model, d)
    dt, weight = robot.dt, robot.weight
    jf = JointVelocityFilter(1, dt, tuning.encoder_std, tuning.joint_vel_std, tuning.joint_accel_density)
    reading_cov = np.diag([tuning.encoder_std**2, tuning.joint_vel_std**2])
    gain2 = (contact.acceleration_gains(d) ** 2).sum(axis=2)  # (2, 6): per (rad/s^2)^2
    for n in range(TORQUE_WINDOW, TORQUE_WINDOW_MAX + 1):
        qdd_var = second_difference_variance(jf.a, jf.gain, reading_cov, n) / (n * dt) ** 4
        noise = math.sqrt(float(gain2[:, 2].max()) * qdd_var) / weight
        if noise <= TORQUE_NOISE_SHARE * TORQUE_FORCE_STD:
            break
    cop_std = math.sqrt(float(gain2[:, 3:5].max()) * qdd_var) / (weight / 2)  # eq. (4) at r = 0
    return n, max(TORQUE_FORCE_STD, noise), cop_std


def _with_mu(gains: Any, mu: float) -> Any:
    return replace(gains, mu=mu)
