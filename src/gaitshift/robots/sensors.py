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

A robot that sees the ground carries a depth camera (``depth_camera``): a pinhole of ``pixels`` =
(columns, rows) rays over the field of view ``fov`` = (horizontal, vertical) rad, mounted on ``body`` at
``pos``, ``quat`` (the site :data:`DEPTH_CAMERA_SITE`, added to every model; its +x is the optical
axis, +y the image's left, +z the image's up, the URDF convention of a camera link). It returns,
``rate`` times a second, the points it hit within ``range`` = (min, max) m, in its own frame, each
range ``r`` off by a normal draw of standard deviation

.. math:: \\sigma(r) = \\sigma_0 + k r^2 \\qquad (``noise: [sigma_0, k]``, m and 1/m)

(the quadratic growth of a stereo camera's depth error), and each pixel lost with probability
``dropout``. The G1 YAML carries its head's Intel RealSense D435i: mounted on ``torso_link`` where
Unitree's URDF puts ``d435_joint``, 87 x 58 deg, 0.3-3 m, 30 Hz, decimated to 32 x 24 rays, about 2 %
of depth error at 2 m (Intel's datasheet: <= 2 % RMS at 2 m).

``foot_force`` says what the real robot reports: without it (the default, and the real G1's
``LowState_``) the controller senses contact from the motors' torques
(:mod:`gaitshift.control.estimation.torque_contact`); with it, from the sole forces.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from gaitshift.errors import InputError

__all__ = ["ADDED_IMU_SITE", "DEPTH_CAMERA_SITE", "DepthCamera", "ImuMount", "RobotSensors", "robot_sensors"]

#: the site gaitshift adds for an IMU given as a body and an offset
ADDED_IMU_SITE = "gaitshift_imu"
#: the site gaitshift adds at a depth camera's mount
DEPTH_CAMERA_SITE = "gaitshift_depth_camera"


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
class DepthCamera:
    """A depth camera (module docstring); lengths m, angles rad, ``rate`` Hz.

    Attributes:
        body, pos (3,), quat (4,) w x y z: the mount (the site :data:`DEPTH_CAMERA_SITE`).
        fov: (horizontal, vertical) field of view. pixels: (columns, rows) rays.
        range: (min, max) distance of a valid return. rate: frames per second.
        noise: (sigma_0 m, k 1/m) of the range error. dropout: probability of losing a pixel.
    """

    body: str
    pos: tuple[float, float, float]
    quat: tuple[float, float, float, float]
    fov: tuple[float, float]
    pixels: tuple[int, int]
    range: tuple[float, float]
    rate: float
    noise: tuple[float, float]
    dropout: float

    def rays(self) -> np.ndarray:
        """The pixels' unit ray directions (rows x columns, 3) in the camera frame, row by row from the
        image's top left: ``(1, -u, -v) / |.|`` with ``u, v`` the pixel centres on the image plane at
        unit distance, ``u`` in ``[-tan(fov_h / 2), tan(fov_h / 2)]``."""
        cols, rows = self.pixels
        u = np.tan(self.fov[0] / 2) * ((2 * np.arange(cols) + 1) / cols - 1)
        v = np.tan(self.fov[1] / 2) * ((2 * np.arange(rows) + 1) / rows - 1)
        uu, vv = np.meshgrid(u, v)
        d = np.stack([np.ones(uu.size), -uu.ravel(), -vv.ravel()], axis=1)
        out: np.ndarray = d / np.linalg.norm(d, axis=1, keepdims=True)
        return out

    def add_site(self, spec: Any) -> None:
        """Add the camera's site to ``spec`` (an ``MjSpec`` of the robot's MJCF)."""
        spec.body(self.body).add_site(name=DEPTH_CAMERA_SITE, pos=list(self.pos), quat=list(self.quat), group=5)


@dataclass(frozen=True)
class RobotSensors:
    """What the robot measures (module docstring).

    Attributes:
        imu: the IMU frame.
        foot_force: the soles carry force sensors.
        depth_camera: the camera that sees the ground, or None.
    """

    imu: ImuMount
    foot_force: bool = False
    depth_camera: DepthCamera | None = None

    def add_sites(self, spec: Any) -> None:
        """Add the sensors' sites gaitshift owns (a body-mounted IMU, the depth camera) to ``spec``."""
        self.imu.add_site(spec)
        if self.depth_camera is not None:
            self.depth_camera.add_site(spec)

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
    camera = _depth_camera(given.depth_camera, model)
    return RobotSensors(_imu(given.imu, model, base), bool(given.foot_force), camera)


def _has(model: Any, kind: str, name: str) -> bool:
    import mujoco

    return bool(mujoco.mj_name2id(model, getattr(mujoco.mjtObj, kind), name) >= 0)


def _imu(imu: Any, model: Any, base: str) -> ImuMount:
    """The IMU mount of the YAML's ``sensors.imu`` (:func:`robot_sensors`)."""
    if imu.site is not None:
        if not _has(model, "mjOBJ_SITE", imu.site):
            raise InputError("robot.sensors.imu.site", imu.site, "a site of the robot's MJCF")
        return ImuMount(imu.site)
    body = imu.body if imu.body is not None else base
    if not _has(model, "mjOBJ_BODY", body):
        raise InputError("robot.sensors.imu.body", body, "a body of the robot's MJCF")
    if _has(model, "mjOBJ_SITE", ADDED_IMU_SITE):
        raise InputError("robot.sensors.imu", ADDED_IMU_SITE, "a model without a site of that name")
    pos = tuple(float(x) for x in imu.pos)
    quat = tuple(float(x) for x in imu.quat)
    return ImuMount(ADDED_IMU_SITE, body, pos, quat)  # type: ignore[arg-type]


def _depth_camera(cam: Any, model: Any) -> DepthCamera | None:
    """The depth camera of the YAML's ``sensors.depth_camera`` (None: the robot has none)."""
    if cam is None:
        return None
    if not _has(model, "mjOBJ_BODY", cam.body):
        raise InputError("robot.sensors.depth_camera.body", cam.body, "a body of the robot's MJCF")
    q = np.asarray(cam.quat, dtype=float)
    return DepthCamera(
        cam.body, tuple(float(x) for x in cam.pos), tuple(float(x) for x in q / np.linalg.norm(q)),  # type: ignore[arg-type]
        (float(cam.fov[0]), float(cam.fov[1])), (int(cam.pixels[0]), int(cam.pixels[1])),
        (float(cam.range[0]), float(cam.range[1])), float(cam.rate),
        (float(cam.noise[0]), float(cam.noise[1])), float(cam.dropout),
    )  # fmt: skip
