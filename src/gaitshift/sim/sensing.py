"""The truth barrier: per tick, what the controller is allowed to know, on its own ``MjData``.

The plant's ``MjData`` is read here only by the sensor model (:mod:`gaitshift.sim.sensors`) and, for
``state="oracle"``, by the copy of the true state; it is written only with the actuator command
(:meth:`Sensing.actuate`). Per tick::

    readings = sensors(plant)                         IMU, encoders, driver velocity, sole forces
    x_hat    = estimator.step(readings, planned)      StateEstimator (inekf by default); planned: the plan's
                                                      contact flags at this tick (the fused contact)
    x_ctrl   = x_hat  (estimated)  |  x_true (oracle) one state for controller, re-planner and step feedback
    x_ctrl   = predict(x_ctrl, pending commands)      latency compensation (gaitshift.sim.latency)
    ctrl_data.qpos, qvel = x_ctrl; mj_forward         the controller's OWN MjData (contacts off)

The controller, the re-planner and the capture-point feedback read only :class:`ControllerView`: the
controller's ``MjData`` (CoM = ``subtree_com[0]``, its velocity = ``subtree_linvel[0]``, frames and
Jacobians all from the one estimated state), the stance flags (force-based with hysteresis for the
estimate, the contact list for the oracle) and the slip flags. The estimator also runs in oracle runs
(its output unused), so every run reports how well it tracks (:mod:`gaitshift.sim.estimation_metrics`).

Friction: the controller starts from ``assumed_friction`` and, on the estimated state, multiplies it by
:data:`FRICTION_DROP` at every detected slip onset of a stance sole, down to :data:`FRICTION_MIN`; it
never raises it again within a run. Oracle runs keep it fixed: on the G1 tour (floor friction 1.0)
brief sole slides at running impacts lowered it to 0.23 and worsened the tracking.
"""

from __future__ import annotations

import copy
import time
from dataclasses import dataclass, replace
from typing import Any

import mujoco
import numpy as np

from gaitshift.control.estimation import GyroCalibration, StateEstimator
from gaitshift.control.estimation.contact import noise_thresholds
from gaitshift.control.estimation.filters import FILTERS
from gaitshift.control.estimation.noise import noise_profile
from gaitshift.control.estimation.tuning import FilterTuning
from gaitshift.errors import InputError, number_in
from gaitshift.scenario.sim_settings import FRICTION_RANGE, NOISE_PROFILES, NOISE_SCALE_RANGE, STATE_SOURCES
from gaitshift.sim.contacts import FootContacts
from gaitshift.sim.latency import CommandPipe
from gaitshift.sim.perturb import with_joint_vel_noise
from gaitshift.sim.sensors import SensorModel

#: friction coefficient the controller assumes unless told: conservative against rubber soles on a dry
#: floor (0.6-1.0) and the simulated contact (1.0); the QP's pyramid |fx|, |fy| <= mu fz lets the
#: diagonal reach sqrt(2) mu. 0.35 costs the oracle G1 runs 0.2 cm of CoM RMS (docs/estimation.md)
DEFAULT_ASSUMED_FRICTION = 0.45
FRICTION_DROP = 0.8
FRICTION_MIN = 0.1
#: slip of a stance sole in oracle runs: low-passed horizontal speed (tau s) above this, m/s
SLIP_SPEED, SLIP_TAU = 0.2, 0.03
IMU_SITE = "imu_in_pelvis"
#: how well the start tilt is known, rad: the run starts at rest, standing on a level floor in a known
#: pose (the estimator's reset state); the prior lets the filter separate the accelerometer's turn-on
#: bias from the tilt while the robot stands (a level floor is known to about 1 mrad)
START_TILT_STD = 1e-3
#: samples of the moving average of the sole forces; the thresholds follow from the force noise
#: (gaitshift.control.estimation.contact.noise_thresholds: 4 and 1.5 std of the averaged noise)
CONTACT_WINDOW = 2
#: the robot stands still this long (s) before the run while the estimator averages the gyro: the
#: turn-on gyro bias, unobservable in heading once the robot runs, is calibrated away (eq. (1) of
#: gaitshift.control.estimation.calibration)
GYRO_CALIBRATION_TIME = 2.0


def check_sensing_options(opts: Any) -> None:
    """Raise :class:`InputError` (one line: field, value, allowed) for a bad sensing option of ``opts``
    (a :class:`~gaitshift.sim.loop.SimOptions`)."""
    if opts.state is not None and opts.state not in STATE_SOURCES:
        raise InputError("state", opts.state, "one of: " + ", ".join(STATE_SOURCES))
    if opts.noise not in NOISE_PROFILES:
        raise InputError("noise", opts.noise, "one of: " + ", ".join(NOISE_PROFILES))
    number_in("noise_scale", opts.noise_scale, NOISE_SCALE_RANGE)
    for name in ("friction", "assumed_friction"):
        mu = getattr(opts, name)
        if mu is not None and (
            isinstance(mu, bool) or not isinstance(mu, int | float) or not FRICTION_RANGE[0] <= mu <= FRICTION_RANGE[1]
        ):
            raise InputError(name, mu, f"a friction coefficient in [{FRICTION_RANGE[0]}, {FRICTION_RANGE[1]}]")
    if isinstance(opts.seed, bool) or not isinstance(opts.seed, int) or opts.seed < 0:
        raise InputError("seed", opts.seed, "an integer >= 0")
    if opts.estimator not in FILTERS:
        raise InputError("estimator", opts.estimator, "one of: " + ", ".join(FILTERS))
    CommandPipe.check(opts.latency)


def with_floor_friction(plant: Any, mu: float | None) -> Any:
    """The plant with a copy of its model whose floor (and bumps) set the contact friction to ``mu`` (sliding;
    MuJoCo uses the friction of the geom of higher ``priority``, so the floor gets priority 1), or the
    plant itself when ``mu`` is None."""
    if mu is None:
        return plant
    model = copy.copy(plant.model)
    ground = list(getattr(plant, "ground_geoms", ()) or (plant.floor_geom,))  # the floor, the terrain and the bumps
    model.geom_priority[ground] = int(model.geom_priority.max()) + 1
    model.geom_friction[ground, 0] = float(mu)
    return replace(plant, model=model)


@dataclass(frozen=True)
class ControllerView:
    """What the controller side gets at one tick.

    Attributes:
        data: the controller's own ``MjData`` at the state it acts on (``mj_forward`` and
            ``mj_subtreeVel`` done).
        touching: (2,) bool stance flags; slip: (2,) bool stance soles sliding.
    """

    data: Any
    touching: np.ndarray
    slip: np.ndarray


class _TrueSlip:
    """Slip of the oracle: a sole touching the floor whose low-passed horizontal speed exceeds
    :data:`SLIP_SPEED` (the estimator's rule, on the true sole velocity)."""

    def __init__(self, plant: Any) -> None:
        self.bodies = [s.body for s in plant.soles]
        self.alpha = 1.0 - np.exp(-plant.dt / SLIP_TAU)
        self.lp = np.zeros((2, 2))
        self._twist = np.zeros(6)

    def update(self, model: Any, d: Any, touching: np.ndarray) -> np.ndarray:
        for s, b in enumerate(self.bodies):
            mujoco.mj_objectVelocity(model, d, mujoco.mjtObj.mjOBJ_BODY, b, self._twist, 0)
            self.lp[s] = self.lp[s] + self.alpha * (self._twist[3:5] - self.lp[s]) if touching[s] else 0.0
        slip: np.ndarray = touching & (np.sum(self.lp**2, axis=1) > SLIP_SPEED**2)
        return slip


class Sensing:
    """Sensor model, estimator, latency pipe, friction belief and the controller's ``MjData`` of one
    run (see module docstring).

    Args:
        plant: the simulated plant (its model: the sensors'; the controller's model is a copy with
            contacts disabled: the controller needs no contact list).
        opts: the run's :class:`~gaitshift.sim.loop.SimOptions`.
        qpos0: the known start state (nq,), at rest.
    """

    def __init__(self, plant: Any, opts: Any, qpos0: np.ndarray) -> None:
        check_sensing_options(opts)
        m = plant.model
        self.has_imu = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, IMU_SITE) >= 0
        #: what the controller sees: the option, else the estimate when the model has the IMU
        self.source = opts.state or ("estimated" if self.has_imu else "oracle")
        self.plant, self.oracle = plant, self.source == "oracle"
        self.cmodel = copy.copy(m)
        self.cmodel.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
        self.cdata = mujoco.MjData(m)
        profile = noise_profile(opts.noise).scaled(float(opts.noise_scale))
        self.log = EstimationLog()
        if not self.has_imu:  # no IMU in the model: the truth only, and no estimation metrics
            if not self.oracle:
                raise InputError("--state", opts.state, f"oracle: the robot's model has no IMU site '{IMU_SITE}'")
            self.qpos0 = np.asarray(qpos0, float).copy()
            self.pipe = CommandPipe(self.cmodel, opts.latency, opts.predict_latency)
            self.mu = float(opts.assumed_friction if opts.assumed_friction is not None else DEFAULT_ASSUMED_FRICTION)
            self._slip_prev = np.zeros(2, bool)
            self._true_slip = _TrueSlip(plant)
            return
        # the extra joint-velocity noise reaches the sensors only: the estimator is tuned to the profile
        self.sensors = SensorModel(m, with_joint_vel_noise(profile, opts.joint_vel_noise), opts.seed, IMU_SITE)
        on, off = noise_thresholds(profile.force, CONTACT_WINDOW)
        self.estimator = StateEstimator.from_robot(
            plant.robot,
            plant.dt,
            tuning=FilterTuning.from_profile(profile, plant.dt, init_tilt_std=START_TILT_STD),
            filter=opts.estimator,
            imu_site=IMU_SITE,
            contact_on=on,
            contact_off=off,
            debounce=1,
            contact_window=CONTACT_WINDOW,
        )
        calibration = GyroCalibration.from_samples(
            self.sensors.still_gyro(GYRO_CALIBRATION_TIME), plant.dt, profile.gyro_bias_walk
        )
        self.estimator.reset(qpos0, np.zeros(m.nv), (True, True), calibration)
        self.qpos0 = np.asarray(qpos0, float).copy()
        self.pipe = CommandPipe(self.cmodel, opts.latency, opts.predict_latency)
        self.mu = float(opts.assumed_friction if opts.assumed_friction is not None else DEFAULT_ASSUMED_FRICTION)
        self._slip_prev = np.zeros(2, bool)
        self._true_slip = _TrueSlip(plant)

    def latch(self, d: Any) -> None:
        """Right after ``mj_step`` (before ``mj_forward``): keep what the IMU measured over the step."""
        if self.has_imu:
            self.sensors.latch(d)

    def observe(self, k: int, d: Any, truth: FootContacts, planned: np.ndarray | None = None) -> ControllerView:
        """Tick ``k``: read the sensors of the plant ``d`` (after ``mj_forward``), estimate (with the plan's
        contact flags ``planned`` (2,), the controller's own schedule), choose the controller's state,
        predict it over the latency and fill the controller's ``MjData``."""
        if not self.has_imu:
            return self._truth_view(d, truth)
        if k == 0:  # the known start state (at rest, both feet down): the estimator was reset to it
            q_est, v_est = self.qpos0, np.zeros(self.plant.model.nv)
            touch_est, slip_est, com, com_vel, cost = np.ones(2, bool), np.zeros(2, bool), None, None, 0.0
            fused = touch_est
        else:
            r = self.sensors.read(d)
            t0 = time.perf_counter()
            s = self.estimator.step(r.imu, r.joints, r.forces, planned)
            cost = 1e6 * (time.perf_counter() - t0)
            q_est, v_est, touch_est, slip_est, com, com_vel = s.qpos(), s.qvel(), s.stance, s.slip, s.com, s.com_vel
            fused = s.contact
        if self.oracle:
            q, v, touching = d.qpos.copy(), d.qvel.copy(), truth.touching
            slip = self._true_slip.update(self.plant.model, d, truth.touching)
        else:
            q, v, touching, slip = q_est, v_est, touch_est, slip_est
        q, v = self.pipe.predict(q, v)
        c = self.cdata
        c.qpos[:], c.qvel[:] = q, v
        mujoco.mj_forward(self.cmodel, c)
        mujoco.mj_subtreeVel(self.cmodel, c)
        if com is None:  # tick 0: the start state, which the controller's data holds
            com, com_vel = c.subtree_com[0].copy(), c.subtree_linvel[0].copy()
        self.log.record(q_est, v_est, fused, touch_est, slip_est, com, com_vel, self.mu, cost)
        return ControllerView(data=c, touching=np.asarray(touching, bool), slip=np.asarray(slip, bool))

    def _truth_view(self, d: Any, truth: FootContacts) -> ControllerView:
        """The controller's view from the truth (a model without an IMU: no estimator runs)."""
        slip = self._true_slip.update(self.plant.model, d, truth.touching)
        q, v = self.pipe.predict(d.qpos.copy(), d.qvel.copy())
        c = self.cdata
        c.qpos[:], c.qvel[:] = q, v
        mujoco.mj_forward(self.cmodel, c)
        mujoco.mj_subtreeVel(self.cmodel, c)
        return ControllerView(data=c, touching=np.asarray(truth.touching, bool), slip=np.asarray(slip, bool))

    def friction(self, gains: Any, view: ControllerView) -> Any:
        """The controller's gains with the friction it assumes now (lowered at each slip onset)."""
        onset = view.slip & ~self._slip_prev
        self._slip_prev = view.slip.copy()
        if onset.any() and not self.oracle:  # the oracle keeps main's controller (brief slides happen at mu 1)
            self.mu = max(FRICTION_MIN, FRICTION_DROP * self.mu)
        return gains if gains.mu == self.mu else replace(gains, mu=self.mu)

    def position_std(self) -> float:
        """Std (m) of the controller's base position along x: the estimator's (the InEKF's world-frame
        covariance, error order R, v, p: row 6), 0 on the truth or for a filter without a covariance."""
        filt = self.estimator.filter if self.has_imu and not self.oracle else None
        world_cov = getattr(filt, "world_covariance", None)
        if world_cov is None:
            return 0.0
        return float(np.sqrt(max(world_cov()[6, 6], 0.0)))

    def actuate(self, d: Any, tau: np.ndarray, qdd: np.ndarray | None) -> np.ndarray:
        """Send the command: write into the plant the torques that act now (after the latency)."""
        applied = self.pipe.send(tau, qdd)
        d.ctrl[:] = applied
        return applied


class EstimationLog:
    """Per tick: the estimator's output (used by the controller or not), prefixed ``est_`` in the run's arrays:
    ``est_qpos`` (nq), ``est_qvel`` (nv), ``est_contact`` (the fused contact), ``est_stance`` (the
    force-confirmed stance the controller's scheduler gets), ``est_slip`` (2, bool), ``est_com``,
    ``est_com_vel`` (3), ``est_mu`` (friction assumed), ``est_tick_us`` (estimator cost, µs; 0 at
    tick 0, the known start state)."""

    def __init__(self) -> None:
        self.rows: dict[str, list[Any]] = {
            k: [] for k in ("qpos", "qvel", "contact", "stance", "slip", "com", "com_vel", "mu", "tick_us")
        }

    def record(self, *values: Any) -> None:
        """One row: qpos, qvel, contact, stance, slip, com, com_vel, mu, tick_us."""
        row = dict(zip(self.rows, values, strict=True))
        for key, v in row.items():
            self.rows[key].append(np.array(v, copy=True))

    def arrays(self, n: int) -> dict[str, np.ndarray]:
        """The first ``n`` rows as arrays named ``est_<key>`` (none when no estimator ran)."""
        if not self.rows["qpos"]:
            return {}
        return {f"est_{k}": np.array(v[:n]) for k, v in self.rows.items()}
