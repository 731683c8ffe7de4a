"""The soles of a robot read from its model: contact geoms, sole frame, contact points and sole size.

A sole is a frame fixed on a foot body: origin at the sole centre on the sole plane, z axis normal to
the sole (up when the robot stands), x axis forward. Its rotation in the body frame R_bs is

* ``body`` (default): the body frame itself (G1, T1, H1, OP3: foot links aligned with the world);
* ``geoms``: the frame of the foot's largest collision box (z = its thinnest axis, pointing from the box
  towards the body origin; x = its longest axis, pointing forward with the model at ``qpos0``);
* a quaternion [w, x, y, z] per side given in the robot YAML.

The contact geoms of a foot are its collision geoms (``contype`` or ``conaffinity`` non-zero); a foot
whose geoms all have collisions off (Apollo, which collides only through ``<pair>`` elements of its
scene) uses its primitive (non-mesh) geoms, and the plant switches their collisions on.

The contact points are the lowest points of those geoms along the sole normal: the bottom of a sphere,
the two bottom points of a capsule, the lowest corners of any other geom's bounding box, kept when
within :data:`FLAT_TOL` of the lowest. The sole centre defaults to the centre of their bounding
rectangle on the sole plane, and the sole size to its sides.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

#: contact points higher than the lowest one by more than this (m) are not on the sole plane
FLAT_TOL = 0.003


@dataclass(frozen=True)
class SoleGeometry:
    """One sole read from the model.

    Attributes:
        geoms: contact geom ids of the foot.
        rotation: (3, 3) R_bs, sole frame in the body frame.
        centre: (3,) sole centre in the body frame, m.
        points: (n, 3) contact points in the sole frame relative to the centre, m (z = 0 on a flat sole).
        size: (length, width) of the bounding rectangle of the points, m.
    """

    geoms: tuple[int, ...]
    rotation: np.ndarray
    centre: np.ndarray
    points: np.ndarray
    size: tuple[float, float]

    @property
    def quat(self) -> tuple[float, float, float, float]:
        """The sole frame in the body frame as a quaternion (w, x, y, z)."""
        import mujoco

        q = np.empty(4)
        mujoco.mju_mat2Quat(q, np.ascontiguousarray(self.rotation, dtype=float).ravel())
        return (float(q[0]), float(q[1]), float(q[2]), float(q[3]))


def common_size(soles: tuple[SoleGeometry, ...]) -> tuple[float, float]:
    """The (length, width) of the sole rectangle every sole holds: the least of each, m (0.1 mm)."""
    return round(min(s.size[0] for s in soles), 4), round(min(s.size[1] for s in soles), 4)


def contact_geoms(model: Any, body: int) -> tuple[tuple[int, ...], bool]:
    """Contact geoms of ``body`` and whether their collisions must be switched on (see module docstring)."""
    import mujoco

    on_body = np.flatnonzero(model.geom_bodyid == body)
    colliding = [int(g) for g in on_body if model.geom_contype[g] or model.geom_conaffinity[g]]
    if colliding:
        return tuple(colliding), False
    prims = [int(g) for g in on_body if int(model.geom_type[g]) != int(mujoco.mjtGeom.mjGEOM_MESH)]
    return tuple(prims), True


def _geom_rotation(model: Any, g: int) -> np.ndarray:
    import mujoco

    R = np.empty(9)
    mujoco.mju_quat2Mat(R, model.geom_quat[g])
    return R.reshape(3, 3)


def _candidates(model: Any, g: int, down: np.ndarray) -> np.ndarray:
    """Candidate lowest points of geom ``g`` in its body frame along ``down`` (unit, body frame): (k, 3)."""
    import mujoco

    pos, R, size = model.geom_pos[g], _geom_rotation(model, g), model.geom_size[g]
    kind = int(model.geom_type[g])
    if kind == int(mujoco.mjtGeom.mjGEOM_SPHERE):
        return np.array([pos + size[0] * down])
    if kind == int(mujoco.mjtGeom.mjGEOM_CAPSULE):
        axis = R[:, 2] * size[1]
        return np.array([pos + axis + size[0] * down, pos - axis + size[0] * down])
    centre, half = model.geom_aabb[g, :3], model.geom_aabb[g, 3:]
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], float)
    return np.asarray(pos + (centre + signs * half) @ R.T)


def sole_rotation(model: Any, body: int, geoms: tuple[int, ...], spec: Any) -> np.ndarray:
    """R_bs (3, 3) from the YAML value ``spec``: ``"body"``, ``"geoms"`` or a quaternion [w, x, y, z]."""
    import mujoco

    from gaitshift.errors import InputError

    if spec == "body":
        return np.eye(3)
    if spec == "geoms":
        boxes = [g for g in geoms if int(model.geom_type[g]) == int(mujoco.mjtGeom.mjGEOM_BOX)]
        if not boxes:
            raise InputError("robot.sole_orientation", "geoms", "'body' or quaternions: the foot has no box geom")
        g = max(boxes, key=lambda b: float(np.prod(np.sort(model.geom_size[b])[1:])))
        R, order = _geom_rotation(model, g), np.argsort(model.geom_size[g])
        z, x = R[:, order[0]], R[:, order[2]]
        if z @ (-model.geom_pos[g]) < 0:
            z = -z
        data = mujoco.MjData(model)
        mujoco.mj_kinematics(model, data)
        forward = data.xmat[1].reshape(3, 3)[:, 0]  # the root body's x axis at qpos0
        if (data.xmat[body].reshape(3, 3) @ x) @ forward < 0:
            x = -x
        return np.column_stack([x, np.cross(z, x), z])
    q = np.asarray(spec, float)
    R9 = np.empty(9)
    mujoco.mju_quat2Mat(R9, q / np.linalg.norm(q))
    return R9.reshape(3, 3)


def sole_geometry(model: Any, body: int, spec: Any, centre: tuple[float, float, float] | None) -> SoleGeometry:
    """The sole of foot ``body`` (see module docstring); ``centre`` (body frame, m) overrides the derived one.

    Raises:
        InputError: the foot body has no geom to stand on.
    """
    from gaitshift.errors import InputError

    geoms, _ = contact_geoms(model, body)
    if not geoms:
        raise InputError("robot.soles", model.body(body).name, "a foot body with collision geoms")
    R = sole_rotation(model, body, geoms, spec)
    down = -R[:, 2]
    pts = np.vstack([_candidates(model, g, down) for g in geoms]) @ R  # sole axes, body origin
    low = pts[pts[:, 2] <= pts[:, 2].min() + FLAT_TOL]
    lo, hi = low[:, :2].min(axis=0), low[:, :2].max(axis=0)
    if centre is None:
        c_s = np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, low[:, 2].min()])
        c_b = R @ c_s
    else:
        c_b = np.asarray(centre, float)
        c_s = R.T @ c_b
    return SoleGeometry(
        geoms=geoms,
        rotation=R,
        centre=c_b,
        points=low - c_s,
        size=(float(hi[0] - lo[0]), float(hi[1] - lo[1])),
    )
