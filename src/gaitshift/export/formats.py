"""The motion file formats, one row each in :data:`FORMATS`.

``unitree-csv``: the layout of Unitree's retargeted motion datasets (also read by BeyondMimic and
mjlab's ``csv_to_npz``). No header, comma separated, one row per frame::

    x y z  qx qy qz qw  q_1 ... q_J

root (floating-base body) position, m, and orientation (scalar last), then the joint angles, rad, in
the MJCF's actuated-joint order (:func:`gaitshift.export.kinematics.actuated_joints`). Default 30 fps;
the file does not store the rate.

``mjlab-npz``: the motion file of mjlab's tracking task (``MotionLoader`` of
``mjlab/tasks/tracking/mdp/commands.py``), an uncompressed ``np.savez``:

==================  ============  ========================================================
key                 shape         meaning
==================  ============  ========================================================
``fps``             (1,) int64    frame rate, Hz
``joint_pos``       (F, J)        joint angles, rad, MuJoCo joint order (qpos order)
``joint_vel``       (F, J)        joint speeds, rad/s, same order
``body_pos_w``      (F, B, 3)     body frame origins, world, m; B = every body but the world
``body_quat_w``     (F, B, 4)     body orientations, world, w x y z, continuous in time
``body_lin_vel_w``  (F, B, 3)     linear velocity of each body frame origin, world, m/s
``body_ang_vel_w``  (F, B, 3)     angular velocity of each body, world, rad/s
``joint_names``     (J,) str      names of the joints (extra: mjlab ignores it)
``body_names``      (B,) str      names of the bodies (extra)
==================  ============  ========================================================

Bodies are in MuJoCo body order (body 0 of the file is the floating base). Default 50 fps.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.export import kinematics as kin


@dataclass(frozen=True)
class Frames:
    """The resampled motion: ``fps`` (Hz), ``qpos`` (F, nq), ``qvel`` (F, nv), of ``model``."""

    fps: int
    qpos: np.ndarray
    qvel: np.ndarray
    model: Any


def write_unitree_csv(frames: Frames, path: Path) -> None:
    """Write ``frames`` as ``unitree-csv`` (see module docstring) to ``path``."""
    m, q = frames.model, frames.qpos
    cols = kin.qpos_columns(m, kin.actuated_joints(m))
    rows = np.hstack([q[:, 0:3], q[:, 4:7], q[:, 3:4], q[:, cols]])
    np.savetxt(path, rows, delimiter=",", fmt="%.9g")


def write_mjlab_npz(frames: Frames, path: Path) -> None:
    """Write ``frames`` as ``mjlab-npz`` (see module docstring) to ``path``."""
    m = frames.model
    names = kin.joint_names(m)
    bodies = kin.body_states(m, frames.qpos, frames.qvel)
    with open(path, "wb") as fh:
        np.savez(
            fh,
            fps=np.array([frames.fps], dtype=np.int64),
            joint_pos=frames.qpos[:, kin.qpos_columns(m, names)],
            joint_vel=frames.qvel[:, kin.qvel_columns(m, names)],
            body_pos_w=bodies["body_pos_w"],
            body_quat_w=bodies["body_quat_w"],
            body_lin_vel_w=bodies["body_lin_vel_w"],
            body_ang_vel_w=bodies["body_ang_vel_w"],
            joint_names=np.array(names),
            body_names=np.array(kin.body_names(m)),
        )


@dataclass(frozen=True)
class ExportFormat:
    """One motion format: its file ``suffix``, ``default_fps`` (Hz), ``write`` (frames, path) and, for a
    consumer that plays every frame as one step of its own, ``fixed_fps``: the only rate it reads right."""

    name: str
    suffix: str
    default_fps: int
    write: Callable[[Frames, Path], None]
    fixed_fps: int | None = None


#: format name -> how to write it
FORMATS: dict[str, ExportFormat] = {
    f.name: f
    for f in (
        ExportFormat("unitree-csv", ".csv", 30, write_unitree_csv),
        # mjlab's MotionLoader ignores the file's fps and plays one frame per 50 Hz step of its
        # tracking task (1.6.0): a 30 fps file would play 1.67 times too fast
        ExportFormat("mjlab-npz", ".npz", 50, write_mjlab_npz, fixed_fps=50),
    )
}
