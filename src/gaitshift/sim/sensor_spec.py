"""Sole force sensors added to the plant's model: one MuJoCo ``touch`` sensor per sole.

A ``touch`` sensor reads the sum of the normal forces of the contacts of its site's body whose contact
point lies inside the site's volume (MuJoCo's documentation, "touch"): the signal a load cell under the
sole gives. Each sole gets a box site enclosing its collision spheres (their centres' x/y extent grown
by 2 radii, from 3 radii below the centres to 1 radius above), so every contact of that sole counts and
nothing else does. The controller side never reads MuJoCo's contact list: the force signal reaches it
only through the sensor model (:mod:`gaitshift.sim.sensors`) and the estimator's contact detector.
"""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np

#: touch sensor names, (left, right)
SOLE_TOUCH_SENSORS = ("gaitshift_left_sole_touch", "gaitshift_right_sole_touch")


def add_sole_touch_sensors(spec: Any, sole_bodies: tuple[str, str]) -> None:
    """Add a box site around the sphere geoms of each sole body of ``spec`` (an ``MjSpec``) and a
    ``touch`` sensor on it (names :data:`SOLE_TOUCH_SENSORS`). A sole without sphere geoms gets a box
    around all its geoms' centres with a 2 cm margin."""
    for name, body_name in zip(SOLE_TOUCH_SENSORS, sole_bodies, strict=True):
        body = spec.body(body_name)
        geoms = [g for g in body.geoms if g.type == mujoco.mjtGeom.mjGEOM_SPHERE] or list(body.geoms)
        centres = np.array([g.pos for g in geoms], dtype=float)
        r = max((float(g.size[0]) for g in geoms if g.type == mujoco.mjtGeom.mjGEOM_SPHERE), default=0.01)
        lo = centres.min(axis=0) - np.array([2 * r, 2 * r, 3 * r])
        hi = centres.max(axis=0) + np.array([2 * r, 2 * r, r])
        site = body.add_site(
            name=name.removesuffix("_touch") + "_zone",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            pos=(lo + hi) / 2,
            size=(hi - lo) / 2,
            group=5,
        )
        spec.add_sensor(
            name=name, type=mujoco.mjtSensor.mjSENS_TOUCH, objtype=mujoco.mjtObj.mjOBJ_SITE, objname=site.name
        )


#: the site the world adds at the floating base for a model that ships no IMU
ADDED_IMU_SITE = "gaitshift_imu"


def add_imu_sensors(spec: Any) -> str:
    """The IMU site of ``spec`` (an ``MjSpec``): the model's own (:data:`gaitshift.robots.model.IMU_SITE`
    with a gyro and an accelerometer), else a site :data:`ADDED_IMU_SITE` at the origin of the floating
    base (the body of the free joint) with a gyro and an accelerometer added. Returns the site name."""
    from gaitshift.robots.model import IMU_SITE

    kinds = {mujoco.mjtSensor.mjSENS_GYRO, mujoco.mjtSensor.mjSENS_ACCELEROMETER}
    have = {s.type for s in spec.sensors if s.objtype == mujoco.mjtObj.mjOBJ_SITE and s.objname == IMU_SITE}
    if kinds <= have:
        return IMU_SITE
    base = next(b for b in spec.bodies if any(j.type == mujoco.mjtJoint.mjJNT_FREE for j in b.joints))
    base.add_site(name=ADDED_IMU_SITE, pos=(0.0, 0.0, 0.0), group=5)
    for kind, suffix in ((mujoco.mjtSensor.mjSENS_GYRO, "gyro"), (mujoco.mjtSensor.mjSENS_ACCELEROMETER, "accel")):
        spec.add_sensor(
            name=f"{ADDED_IMU_SITE}_{suffix}", type=kind, objtype=mujoco.mjtObj.mjOBJ_SITE, objname=ADDED_IMU_SITE
        )
    return ADDED_IMU_SITE
