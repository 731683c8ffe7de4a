"""The robot's sensors (robot YAML ``sensors``): where its IMU sits, and whether its soles measure force.

The estimator reads the IMU's gyro and accelerometer in the IMU frame, a site of the model. A robot
YAML names that frame in one of two ways::

    sensors:
      imu: {site: imu_in_pelvis}                          # a site of the MJCF (the G1's pelvis IMU)
      imu: {body: pelvis, pos: [0, 0, 0.05], quat: [1, 0, 0, 0]}   # or a body and an offset, m
      foot_force: false                                   # load cells under the soles (default: none)

Without ``imu`` the IMU sits at the origin of the floating base (the body of the free joint), the
place most humanoids carry theirs. A body-mounted IMU becomes the site :data:`ADDED_IMU_SITE`, added to
every model of the robot (the controller's, the IK's and the simulated world's), so that both sides of
the truth barrier name the same frame. When the model has no gyro or accelerometer on that site, the
simulated world adds them (:func:`gaitshift.sim.sensor_spec.add_imu_sensors`) and passes their
readings through the noise profile like the G1's own.

``foot_force`` says what the real robot reports: without it (the default, and the real G1's
``LowState_``) the controller senses contact from the motors' torques
(:mod:`gaitshift.control.estimation.torque_contact`); with it, from the sole forces.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from gaitshift.errors import InputError

__all__ = ["ADDED_IMU_SITE", "ImuMount", "RobotSensors", "robot_sensors"]

#: the site gaitshift adds for an IMU given as a body and an offset
ADDED_IMU_SITE = "gaitshift_imu"


@dataclass(frozen=True)
class ImuMount:
    """The IMU frame of a robot.

    Attributes:
        site: name of the IMU site (the model's own, or :data:`ADDED_IMU_SITE`).
        body: the body the added site sits on; None when ``site`` is the model's own.
        pos: (3,) the added site's position in the body frame, m.
        quat: (4,) the added site's orientation in the body frame, (w, x, y, z).
    """

    site: str
    body: str | None = None
    pos: tuple[float, float, float] = (0.0, 0.0, 0.0)
    quat: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)

    def add_site(self, spec: Any) -> None:
        """Add the IMU site to ``spec`` (an ``MjSpec`` of the robot's MJCF) when the model has none."""
        if self.body is not None:
            spec.body(self.body).add_site(name=self.site, pos=list(self.pos), quat=list(self.quat), group=5)


@dataclass(frozen=True)
class RobotSensors:
    """What the robot measures (module docstring).

    Attributes:
        imu: the IMU frame.
        foot_force: the soles carry force sensors.
    """

    imu: ImuMount
    foot_force: bool = False

    @property
    def contact(self) -> str:
        """Where the controller's contact sensing comes from by default: ``"force"`` or ``"torque"``."""
        return "force" if self.foot_force else "torque"


def robot_sensors(given: Any, model: Any, base: str) -> RobotSensors:
    """The sensors of the YAML's ``sensors`` value ``given`` (:class:`gaitshift.robots.schema.Sensors`)
    checked against ``model`` (the MJCF as shipped); ``base`` is the floating base's body name.

    Raises:
        InputError: an IMU site or body that is not in the model, or a body-mounted IMU whose site
            name the model already uses.
    """
    import mujoco

    imu = given.imu
    if imu.site is not None:
        if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, imu.site) < 0:
            raise InputError("robot.sensors.imu.site", imu.site, "a site of the robot's MJCF")
        return RobotSensors(ImuMount(imu.site), bool(given.foot_force))
    body = imu.body if imu.body is not None else base
    if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, body) < 0:
        raise InputError("robot.sensors.imu.body", body, "a body of the robot's MJCF")
    if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, ADDED_IMU_SITE) >= 0:
        raise InputError("robot.sensors.imu", ADDED_IMU_SITE, "a model without a site of that name")
    pos = tuple(float(x) for x in imu.pos)
    quat = tuple(float(x) for x in imu.quat)
    return RobotSensors(ImuMount(ADDED_IMU_SITE, body, pos, quat), bool(given.foot_force))  # type: ignore[arg-type]
