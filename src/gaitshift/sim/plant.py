"""The simulated plant: the robot's model (:mod:`gaitshift.robots.model`) in a world.

The world compiles the robot's spec (:func:`gaitshift.robots.model.robot_spec`: the MJCF with sole
sites and torque motors) with these additions, documented in docs/simulation.md:

* a floor plane (``floor``, the MJCF's default geom class) when the MJCF has no plane in its world body;
* the scenario's terrain, one box per piece with the floor's contact parameters (:mod:`gaitshift.sim.terrain_geoms`);
* the bumps asked for (``SimOptions.bumps``, :mod:`gaitshift.sim.bumps`): boxes on the floor;
* the sensors (:mod:`gaitshift.sim.sensor_spec`): a touch sensor under each sole, and a gyro and an
  accelerometer on the robot's IMU site (``sensors.imu`` of the robot YAML) when the model has none there.

None of them moves a body or a joint: the controller's own model (the robot's alone) computes the same
kinematics and dynamics to the last bit.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import mujoco
import numpy as np

from gaitshift.models.terrain import FLAT, Terrain
from gaitshift.robots.config import RobotConfig, load_robot
from gaitshift.robots.model import RobotModel, check_period, compile_spec, robot_spec
from gaitshift.sim.bumps import Bump, add_bumps
from gaitshift.sim.sensor_spec import add_imu_sensors, add_sole_touch_sensors
from gaitshift.sim.terrain_geoms import add_terrain

#: name of the floor geom added to an MJCF that has none
FLOOR = "floor"


@dataclass(frozen=True)
class Plant(RobotModel):
    """The robot's model in the world: a :class:`~gaitshift.robots.model.RobotModel` with the ground.

    Attributes:
        floor_geom: geom id of the floor plane.
        ground_geoms: geom ids of the ground the feet stand on: the floor, then the terrain boxes and the bumps.
        imu: the IMU site (the robot YAML's ``sensors.imu``), where the world's gyro and accelerometer are.
    """

    floor_geom: int = 0
    ground_geoms: tuple[int, ...] = ()
    imu: str = ""


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
    return _build(check_period(control_period), load_robot(robot), terrain, tuple(bumps))


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


@lru_cache(maxsize=8)
def _build(dt: float, robot: RobotConfig, terrain: Terrain, bumps: tuple[Bump, ...] = ()) -> Plant:
    spec = robot_spec(robot)
    _floor(spec)
    add_terrain(spec, terrain)
    add_bumps(spec, bumps)
    add_sole_touch_sensors(spec, robot)
    add_imu_sensors(spec, robot.imu_site)
    model, fields = compile_spec(spec, robot, dt)
    planes = np.flatnonzero((model.geom_bodyid == 0) & (model.geom_type == mujoco.mjtGeom.mjGEOM_PLANE))
    boxes = [i for i in np.flatnonzero(model.geom_bodyid == 0) if i != planes[0]]  # terrain and bumps
    ground = (int(planes[0]), *(int(i) for i in boxes))
    return Plant(model=model, robot=robot, floor_geom=int(planes[0]), ground_geoms=ground, imu=robot.imu_site, **fields)  # type: ignore[arg-type]
