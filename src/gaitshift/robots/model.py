"""The robot's compiled model with torque motors: what the controller and the simulated world share.

The model is the robot config's MJCF as shipped (masses, inertias, joint armature, damping and
friction loss, contact parameters, solver options) with these changes, documented in
docs/simulation.md and docs/robots.md:

* the two sole sites of the config (:mod:`gaitshift.robots.mjcf`), and the IMU site when the robot YAML
  mounts the IMU on a body (:mod:`gaitshift.robots.sensors`);
* the shipped actuators (position servos, motors) are replaced by one ``motor`` actuator per hinge
  joint, gear 1, ``ctrlrange`` = +- the joint's torque limit read from the model
  (``RobotConfig.torque_limit``: ``actuatorfrcrange``, else the force or control range of its motor);
  the motors, in model order, are the robot's motors (:attr:`RobotModel.motor_names`);
* foot geoms whose collisions are all off (a model that collides through ``<pair>`` elements of a
  scene file, e.g. Apollo) get ``contype = conaffinity = 1`` (:func:`gaitshift.robots.soles.contact_geoms`);
* the time step is the control period (default 2 ms) and the integrator ``implicitfast``.

The controller compiles this model alone (:func:`robot_model`); the simulated world
(:mod:`gaitshift.sim.plant`) compiles the same spec with a floor, terrain and sensors added. Neither
addition moves a body or a joint, so kinematics and dynamics agree to the last bit.

The contact points are the lowest points of each foot's contact geoms
(:class:`gaitshift.robots.soles.SoleGeometry`): the four sphere bottoms of the G1, the four bottom
corners of a box sole, the capsule ends of the H1. The floating base is the body of the free joint.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import mujoco
import numpy as np

from gaitshift.errors import InputError
from gaitshift.robots.config import RobotConfig, load_robot
from gaitshift.robots.mjcf import raw_model
from gaitshift.robots.soles import contact_geoms

__all__ = ["PERIOD_RANGE", "RobotModel", "SolePoints", "forward_terms", "robot_model", "robot_spec", "standing_qpos"]

#: the control period = time step a model is compiled with, s
PERIOD_RANGE = (0.001, 0.002)


@dataclass(frozen=True)
class SolePoints:
    """One sole of the model.

    Attributes:
        body: body id; geoms: its contact geom ids.
        centre: (3,) sole centre in the body frame, m; rotation: (3, 3) sole frame in the body frame.
        points: (n, 3) contact points in the sole frame relative to the centre, m.
    """

    body: int
    geoms: tuple[int, ...]
    centre: np.ndarray
    rotation: np.ndarray
    points: np.ndarray


@dataclass(frozen=True)
class RobotModel:
    """A compiled robot model with torque motors, and the indices the controller needs.

    Attributes:
        model: the MuJoCo model (``opt.timestep`` = control period, s).
        soles: [left, right] :class:`SolePoints`.
        torque_limit: (nu,) N m, the motor ctrlrange upper bound (symmetric).
        actuated_dofs: (nu,) dof index of each motor (qvel/qacc index).
        torso_body: body id of the config's torso; pelvis_body: body id of the floating base.
        mass: total mass, kg.
        robot: the robot config the model comes from.
    """

    model: mujoco.MjModel
    soles: tuple[SolePoints, SolePoints]
    torque_limit: np.ndarray
    actuated_dofs: np.ndarray
    torso_body: int
    pelvis_body: int
    mass: float
    robot: RobotConfig

    @property
    def dt(self) -> float:
        return float(self.model.opt.timestep)

    @property
    def weight(self) -> float:
        """N, the robot's weight under the model's gravity (``mass g``)."""
        return self.mass * -float(self.model.opt.gravity[2])

    @property
    def motor_names(self) -> tuple[str, ...]:
        """The motors (= their hinge joints), in the order of every per-motor array."""
        m = self.model
        return tuple(mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_ACTUATOR, i) for i in range(m.nu))

    @property
    def imu_site(self) -> str:
        """The IMU site (the robot YAML's ``sensors.imu``, :mod:`gaitshift.robots.sensors`)."""
        return self.robot.imu_site

    def sole_frame(self, data: mujoco.MjData, side: int) -> tuple[np.ndarray, np.ndarray]:
        """Sole centre (3,) m and sole frame rotation (3, 3) of one foot, world frame."""
        s = self.soles[side]
        Rb = data.xmat[s.body].reshape(3, 3)
        return data.xpos[s.body] + Rb @ s.centre, Rb @ s.rotation

    def contact_points(self, data: mujoco.MjData, side: int) -> np.ndarray:
        """World positions (n, 3) of the contact points of one sole, m."""
        c, R = self.sole_frame(data, side)
        pts: np.ndarray = c + self.soles[side].points @ R.T
        return pts


def forward_terms(model: mujoco.MjModel, data: mujoco.MjData) -> None:
    """The part of ``mj_forward`` a controller reads, at ``data``'s ``qpos``, ``qvel``: ``mj_fwdPosition``
    (the frames, the CoM, ``cdof``, the mass matrix and its factor; collision where the model's contacts are
    on) and ``mj_fwdVelocity`` (``cvel``, ``cdof_dot``, ``qfrc_passive``, ``qfrc_bias`` = ``b`` of eq. (1)
    of :mod:`gaitshift.control.estimation.torque_contact`). Actuation, accelerations, constraint forces and
    sensors are left out: on the G1 with its contacts off this takes 9 us where ``mj_forward`` takes 33 us
    (its accelerometer alone asks for ``mj_rnePostConstraint``)."""
    mujoco.mj_fwdPosition(model, data)
    mujoco.mj_fwdVelocity(model, data)


def check_period(control_period: float) -> float:
    """The control period rounded to 1 µs; :class:`InputError` outside :data:`PERIOD_RANGE`."""
    lo, hi = PERIOD_RANGE
    if (
        isinstance(control_period, bool)
        or not isinstance(control_period, int | float)
        or not lo <= control_period <= hi
    ):
        raise InputError("control_period", control_period, f"a period in [{lo}, {hi}] s")
    return round(float(control_period), 6)


def robot_spec(robot: RobotConfig) -> mujoco.MjSpec:
    """The robot's ``MjSpec``: its MJCF with the sole sites, one torque motor per hinge and the feet
    colliding (see module docstring); no floor, no terrain, no sensors added."""
    spec = mujoco.MjSpec.from_file(str(robot.mjcf))
    robot.add_sites(spec)
    _torque_motors(spec, robot)
    _feet_collide(spec, robot)
    return spec


def compile_spec(spec: mujoco.MjSpec, robot: RobotConfig, dt: float) -> tuple[mujoco.MjModel, dict[str, object]]:
    """Compile ``spec`` at time step ``dt`` (implicitfast) and read the :class:`RobotModel` fields
    (all but ``model`` and ``robot``) from the compiled model."""
    spec.option.timestep = dt
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    model = spec.compile()
    act_dofs = np.array([model.jnt_dofadr[model.actuator_trnid[i, 0]] for i in range(model.nu)])
    soles = []
    for body, geo in zip(robot.sole_bodies, robot.soles, strict=True):
        bid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, body)
        geoms, _ = contact_geoms(model, bid)
        soles.append(SolePoints(int(bid), geoms, geo.centre.copy(), geo.rotation.copy(), geo.points.copy()))
    fields: dict[str, object] = {
        "soles": (soles[0], soles[1]),
        "torque_limit": model.actuator_ctrlrange[:, 1].copy(),
        "actuated_dofs": act_dofs,
        "torso_body": mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, robot.torso),
        "pelvis_body": int(model.jnt_bodyid[0]),
        "mass": float(model.body_subtreemass[0]),
    }
    return model, fields


def robot_model(robot: str | Path | RobotConfig = "g1", control_period: float = 0.002) -> RobotModel:
    """The robot's compiled model (module docstring): ``robot`` a built-in name, a robot YAML path or
    a config; ``control_period`` s in :data:`PERIOD_RANGE`."""
    return _robot_model(load_robot(robot), check_period(control_period))


@lru_cache(maxsize=8)
def _robot_model(robot: RobotConfig, dt: float) -> RobotModel:
    model, fields = compile_spec(robot_spec(robot), robot, dt)
    return RobotModel(model=model, robot=robot, **fields)  # type: ignore[arg-type]


def _torque_motors(spec: mujoco.MjSpec, robot: RobotConfig) -> None:
    """Replace the shipped actuators by one torque motor per hinge, limited to its torque limit."""
    limits = dict(zip(robot.joint_names, robot.torque_limit, strict=True))
    for act in list(spec.actuators):
        spec.delete(act)
    for j in spec.joints:
        if j.type != mujoco.mjtJoint.mjJNT_HINGE:
            continue
        lim = float(limits[j.name])
        if not np.isfinite(lim):
            raise InputError(
                "robot.mjcf", str(robot.mjcf), f"a torque limit for joint {j.name} (actuatorfrcrange or a motor range)"
            )
        spec.add_actuator(
            name=j.name,
            target=j.name,
            trntype=mujoco.mjtTrn.mjTRN_JOINT,
            gainprm=[1.0] + [0.0] * 9,
            biasprm=[0.0] * 10,
            ctrllimited=mujoco.mjtLimited.mjLIMITED_TRUE,
            ctrlrange=[-lim, lim],
        )


def _feet_collide(spec: mujoco.MjSpec, robot: RobotConfig) -> None:
    """Switch collisions on for the foot geoms of a foot whose geoms all have them off."""
    raw = raw_model(robot.mjcf)
    for body in robot.sole_bodies:
        _, enable = contact_geoms(raw, raw.body(body).id)
        if enable:
            for g in spec.body(body).geoms:
                if g.type != mujoco.mjtGeom.mjGEOM_MESH:
                    g.contype, g.conaffinity = 1, 1


def standing_qpos(robot: RobotModel, flexion: float | None = None) -> np.ndarray:
    """The robot config's standing pose (``RobotConfig.standing_qpos``) on the floor: (nq,), base
    upright at the origin of the ground plane, lowered until the lower sole centre touches z = 0.

    ``flexion`` scales the standing pose's leg joint angles (1: the pose itself; smaller: straighter
    legs, larger: deeper knee bend; clipped to the joint ranges). Soles parallel in the standing pose
    stay parallel when the pose's hip, knee and ankle pitch angles sum to zero.
    """
    m = robot.model
    q: np.ndarray = robot.robot.standing_qpos(m)
    if flexion is not None:
        for joint in robot.robot.leg_joints:
            jid = m.joint(joint).id
            adr = m.jnt_qposadr[jid]
            lo, hi = m.jnt_range[jid] if m.jnt_limited[jid] else (-np.inf, np.inf)
            q[adr] = np.clip(q[adr] * flexion, lo, hi)
    d = mujoco.MjData(m)
    d.qpos[:] = q
    mujoco.mj_kinematics(m, d)
    q[2] -= min(float(np.min(robot.contact_points(d, s)[:, 2])) for s in (0, 1))
    return q
