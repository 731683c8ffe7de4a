"""Rotations and angles shared by the planners, the IK, the controller and the renderer (rad, z up)."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

__all__ = ["mid_yaw", "rot2", "rot_y", "rot_z", "wrap_angle"]


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
