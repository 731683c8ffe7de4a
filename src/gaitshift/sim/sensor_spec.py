"""The sensors the simulated world adds to the plant's model: sole force sensors and the IMU's.

Each sole gets a MuJoCo ``touch`` sensor: the sum of the normal forces of the contacts of its site's
body whose contact point lies inside the site's volume (MuJoCo's documentation, "touch"), the signal a
load cell under the sole gives. The site is a box in the sole frame around the sole's whole contact
footprint (the contact points of :class:`gaitshift.robots.soles.SoleGeometry`, grown by
:data:`ZONE_MARGIN` sideways, from :data:`ZONE_MARGIN` below the sole plane to :data:`ZONE_HEIGHT`
above it), so every contact of that sole counts, on its heel, toe and edges, and nothing else does.
The controller side never reads MuJoCo's contact list: the force signal reaches it only through the
sensor model (:mod:`gaitshift.sim.sensors`) and the estimator's contact detector.
"""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np

#: touch sensor names, (left, right)
SOLE_TOUCH_SENSORS = ("gaitshift_left_sole_touch", "gaitshift_right_sole_touch")
#: growth of the touch zone beyond the contact points along the sole and below its plane, m
ZONE_MARGIN = 0.02
#: height of the touch zone above the sole plane, m (a tilted foot's contacts rise up its geoms' sides)
ZONE_HEIGHT = 0.03


def add_sole_touch_sensors(spec: Any, robot: Any) -> None:
    """Add a box site around the contact footprint of each sole of ``robot`` (a
    :class:`gaitshift.robots.RobotConfig`) to ``spec`` (an ``MjSpec``) and a ``touch`` sensor on it
    (names :data:`SOLE_TOUCH_SENSORS`; module docstring)."""
    for name, body_name, sole in zip(SOLE_TOUCH_SENSORS, robot.sole_bodies, robot.soles, strict=True):
        pts = np.asarray(sole.points, float)
        lo = np.append(pts[:, :2].min(axis=0) - ZONE_MARGIN, -ZONE_MARGIN)
        hi = np.append(pts[:, :2].max(axis=0) + ZONE_MARGIN, ZONE_HEIGHT)
        site = spec.body(body_name).add_site(
            name=name.removesuffix("_touch") + "_zone",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            pos=sole.centre + sole.rotation @ ((lo + hi) / 2),
            quat=sole.quat,
            size=(hi - lo) / 2,
            group=5,
        )
        spec.add_sensor(
            name=name, type=mujoco.mjtSensor.mjSENS_TOUCH, objtype=mujoco.mjtObj.mjOBJ_SITE, objname=site.name
        )


def add_imu_sensors(spec: Any, site: str) -> None:
    """A gyro and an accelerometer on the IMU ``site`` of ``spec`` (an ``MjSpec``), each unless the
    model has one there already (the G1 ships both on ``imu_in_pelvis``)."""
    have = {s.type for s in spec.sensors if s.objtype == mujoco.mjtObj.mjOBJ_SITE and s.objname == site}
    for kind, suffix in ((mujoco.mjtSensor.mjSENS_GYRO, "gyro"), (mujoco.mjtSensor.mjSENS_ACCELEROMETER, "accel")):
        if kind not in have:
            spec.add_sensor(name=f"gaitshift_imu_{suffix}", type=kind, objtype=mujoco.mjtObj.mjOBJ_SITE, objname=site)
