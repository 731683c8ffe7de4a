"""The simulated plant: any robot of :mod:`gaitshift.robots` (its MJCF and YAML) with torque motors.

The model is the robot config's MJCF as shipped (masses, inertias, joint armature, damping and
friction loss, contact parameters, solver options) with these changes, documented in
docs/simulation.md and docs/robots.md:

* the two sole sites of the config (:mod:`gaitshift.robots.mjcf`);
* the shipped actuators (position servos, motors) are replaced by one ``motor`` actuator per hinge
  joint, gear 1, ``ctrlrange`` = +- the joint's torque limit read from the model
  (``RobotConfig.torque_limit``: ``actuatorfrcrange``, else the force or control range of its motor);
* a floor plane (``floor``, the MJCF's default geom class) when the MJCF has no plane in its world body;
* the plan's terrain, one box per piece with the floor's contact parameters (:mod:`gaitshift.sim.terrain_geoms`);
* the bumps asked for (``SimOptions.bumps``, :mod:`gaitshift.sim.bumps`): boxes on the floor;
* foot geoms whose collisions are all off (a model that collides through ``<pair>`` elements of a
  scene file, e.g. Apollo) get ``contype = conaffinity = 1`` (:func:`gaitshift.robots.soles.contact_geoms`);
* the time step is the control period (default 2 ms; the controller computes torques once per physics
  step) and the integrator ``implicitfast``.

The contact points the controller uses are the lowest points of each foot's contact geoms
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
from gaitshift.models.terrain import FLAT, Terrain
from gaitshift.robots.config import RobotConfig, load_robot
from gaitshift.robots.mjcf import raw_model
from gaitshift.robots.soles import contact_geoms
from gaitshift.sim.bumps import Bump, add_bumps
from gaitshift.sim.sensor_spec import add_sole_touch_sensors
from gaitshift.sim.terrain_geoms import add_terrain

#: name of the floor geom added to an MJCF that has none
FLOOR = "floor"


@dataclass(frozen=True)
class SolePoints:
    """One sole of the plant.

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
class Plant:
    """A compiled robot model with torque motors, and the indices the controller needs.

    Attributes:
        model: the MuJoCo model (``opt.timestep`` = control period, s).
        soles: [left, right] :class:`SolePoints`.
        torque_limit: (nu,) N m, the motor ctrlrange upper bound (symmetric).
        actuated_dofs: (nu,) dof index of each motor (qvel/qacc index).
        floor_geom: geom id of the floor plane.
        ground_geoms: geom ids of the ground the feet stand on: the floor, then the terrain boxes and the bumps.
        torso_body: body id of the config's torso; pelvis_body: body id of the floating base.
        mass: total mass, kg.
        robot: the robot config the model comes from.
    """

    model: mujoco.MjModel
    soles: tuple[SolePoints, SolePoints]
    torque_limit: np.ndarray
    actuated_dofs: np.ndarray
    floor_geom: int
    torso_body: int
    pelvis_body: int
    mass: float
    robot: RobotConfig
    ground_geoms: tuple[int, ...] = ()

    @property
    def dt(self) -> float:
        return float(self.model.opt.timestep)

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


def build_plant(
    control_period: float = 0.002,
    robot: str | Path | RobotConfig = "g1",
    terrain: Terrain = FLAT,
    bumps: tuple[Bump, ...] = (),
) -> Plant:
    """Compile ``robot`` with torque motors, a floor, ``terrain`` and ``bumps`` (see module docstring).

    Args:
        control_period: physics time step = control period, s, in [0.001, 0.002].
        robot: built-in name, robot YAML path or config.
        terrain: the ground on the floor (default: none).
        bumps: boxes on the floor (:mod:`gaitshift.sim.bumps`).

    Raises:
        InputError: bad period, or a hinge joint without a torque limit in the model.
    """
    if not (0.001 <= control_period <= 0.002):
        raise InputError("control_period", control_period, "a period in [0.001, 0.002] s")
    return _build(round(control_period, 6), load_robot(robot), terrain, tuple(bumps))


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


def _floor(spec: mujoco.MjSpec) -> None:
    """Add a floor plane when the world body has none.

    Like the floor of a model's own ``scene.xml``, it takes the MJCF's default geom class (its solref,
    solimp and friction, e.g. the OP3's stiff ``solref``), except that it always collides and carries
    friction: ``contype``/``conaffinity`` are MuJoCo's built-in defaults and ``condim`` is at least the
    built-in one (3, a friction cone). A model whose default geom is frictionless and collision-free
    (Apollo: ``condim="1" contype="0"``; its scene adds foot-floor ``<pair>``s) would otherwise have
    its feet pass through the floor, or slide on it.
    """
    if any(g.type == mujoco.mjtGeom.mjGEOM_PLANE for g in spec.worldbody.geoms):
        return
    builtin = mujoco.MjSpec().default.geom
    floor = spec.worldbody.add_geom(name=FLOOR, type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 0.05])
    floor.contype, floor.conaffinity = builtin.contype, builtin.conaffinity
    floor.condim = max(floor.condim, builtin.condim)


def _feet_collide(spec: mujoco.MjSpec, robot: RobotConfig) -> None:
    """Switch collisions on for the foot geoms of a foot whose geoms all have them off."""
    raw = raw_model(robot.mjcf)
    for body in robot.sole_bodies:
        _, enable = contact_geoms(raw, raw.body(body).id)
        if enable:
            for g in spec.body(body).geoms:
                if g.type != mujoco.mjtGeom.mjGEOM_MESH:
                    g.contype, g.conaffinity = 1, 1


@lru_cache(maxsize=8)
def _build(dt: float, robot: RobotConfig, terrain: Terrain, bumps: tuple[Bump, ...] = ()) -> Plant:
    spec = mujoco.MjSpec.from_file(str(robot.mjcf))
    robot.add_sole_sites(spec)
    _torque_motors(spec, robot)
    _floor(spec)
    add_terrain(spec, terrain)
    add_bumps(spec, bumps)
    _feet_collide(spec, robot)
    add_sole_touch_sensors(spec, robot.sole_bodies)  # sensing hook (sim/sensor_spec.py)
    spec.option.timestep = dt
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    model = spec.compile()
    act_dofs = np.array([model.jnt_dofadr[model.actuator_trnid[i, 0]] for i in range(model.nu)])
    soles = []
    for body, geo in zip(robot.sole_bodies, robot.soles, strict=True):
        bid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, body)
        geoms, _ = contact_geoms(model, bid)
        soles.append(SolePoints(int(bid), geoms, geo.centre.copy(), geo.rotation.copy(), geo.points.copy()))
    planes = np.flatnonzero((model.geom_bodyid == 0) & (model.geom_type == mujoco.mjtGeom.mjGEOM_PLANE))
    boxes = [i for i in np.flatnonzero(model.geom_bodyid == 0) if i != planes[0]]  # terrain and bumps
    return Plant(
        model=model,
        soles=(soles[0], soles[1]),
        torque_limit=model.actuator_ctrlrange[:, 1].copy(),
        actuated_dofs=act_dofs,
        floor_geom=int(planes[0]),
        torso_body=mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, robot.torso),
        pelvis_body=int(model.jnt_bodyid[0]),
        mass=float(model.body_subtreemass[0]),
        robot=robot,
        ground_geoms=(int(planes[0]), *(int(i) for i in boxes)),
    )


def standing_qpos(plant: Plant, flexion: float | None = None) -> np.ndarray:
    """The robot config's standing pose (``RobotConfig.standing_qpos``) on the floor: (nq,), base
    upright at the origin of the ground plane, lowered until the lower sole centre touches z = 0.

    ``flexion`` scales the standing pose's leg joint angles (1: the pose itself; smaller: straighter
    legs, larger: deeper knee bend; clipped to the joint ranges). Soles parallel in the standing pose
    stay parallel when the pose's hip, knee and ankle pitch angles sum to zero.
    """
    m = plant.model
    q: np.ndarray = plant.robot.standing_qpos(m)
    if flexion is not None:
        for joint in plant.robot.leg_joints:
            jid = m.joint(joint).id
            adr = m.jnt_qposadr[jid]
            lo, hi = m.jnt_range[jid] if m.jnt_limited[jid] else (-np.inf, np.inf)
            q[adr] = np.clip(q[adr] * flexion, lo, hi)
    d = mujoco.MjData(m)
    d.qpos[:] = q
    mujoco.mj_kinematics(m, d)
    q[2] -= min(float(np.min(plant.contact_points(d, s)[:, 2])) for s in (0, 1))
    return q
