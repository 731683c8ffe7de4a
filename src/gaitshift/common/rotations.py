"""Rotations and angles shared by the planners, the IK, the controller and the renderer (rad, z up)."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

__all__ = ["mid_yaw", "roll_pitch_yaw", "rot2", "rot_y", "rot_z", "tilt_error", "up_in_body", "wrap_angle"]


def rot_z(yaw: float) -> np.ndarray:
    """Rotation about the world z axis by ``yaw`` (rad): the (3, 3) matrix
    ``[[cos, -sin, 0], [sin, cos, 0], [0, 0, 1]]`` (a flat sole or an upright torso with heading ``yaw``)."""
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rot_y(angle: float) -> np.ndarray:
    """Rotation about the y axis by ``angle`` (rad): ``[[cos, 0, sin], [0, 1, 0], [-sin, 0, cos]]``
    (a positive angle turns +x toward -z: a sole on a ramp rising along +x by ``p`` is ``rot_y(-p)``)."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rot2(yaw: float) -> npt.NDArray[np.float64]:
    """Rotation matrix (2, 2) of the plane by ``yaw`` rad (counter-clockwise, z up)."""
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s], [s, c]])


def wrap_angle(a: float) -> float:
    """``a`` wrapped to [-pi, pi), rad."""
    return (a + math.pi) % (2.0 * math.pi) - math.pi


def mid_yaw(a: float, b: float) -> float:
    """The yaw halfway between ``a`` and ``b`` the shorter way round (circular mean), rad."""
    return math.atan2(math.sin(a) + math.sin(b), math.cos(a) + math.cos(b))


def roll_pitch_yaw(quat: npt.ArrayLike) -> np.ndarray:
    """Roll, pitch, yaw (..., 3) rad (z-y-x Euler angles: R = Rz(yaw) Ry(pitch) Rx(roll)) of quaternions
    (..., 4) w, x, y, z; normalised first."""
    q = np.asarray(quat, dtype=float)
    w, x, y, z = np.moveaxis(q / np.linalg.norm(q, axis=-1, keepdims=True), -1, 0)
    roll = np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = np.arcsin(np.clip(2 * (w * y - z * x), -1.0, 1.0))
    yaw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return np.stack([roll, pitch, yaw], axis=-1)


def up_in_body(quat: npt.ArrayLike) -> np.ndarray:
    """The world's z axis in the body frame of unit quaternions (..., 4) w, x, y, z: the third row of the
    rotation, (..., 3). Gravity points along minus it; a rotation about the world's z (a heading) leaves it
    unchanged."""
    w, x, y, z = np.moveaxis(np.asarray(quat, dtype=float), -1, 0)
    return np.stack([2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y)], axis=-1)


def tilt_error(q_est: npt.ArrayLike, q_true: npt.ArrayLike) -> np.ndarray:
    """The tilt error, rad, of an orientation estimate: the angle between the vertical as the two body
    frames see it (quaternions (..., 4) w, x, y, z, normalised here),

    .. math::

        e = \\angle(R_{est}^T e_z,\\; R^T e_z),

    zero for a heading error alone, however the body leans. (The angle between the two body z axes in the
    world, ``angle(R_est e_z, R e_z)``, is not: a heading error ``psi`` on a body leaning by ``theta`` reads
    as about ``psi sin(theta)``.)"""
    qa, qb = np.asarray(q_est, dtype=float), np.asarray(q_true, dtype=float)
    a = up_in_body(qa / np.linalg.norm(qa, axis=-1, keepdims=True))
    b = up_in_body(qb / np.linalg.norm(qb, axis=-1, keepdims=True))
    out: np.ndarray = np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), np.sum(a * b, axis=-1))
    return out
