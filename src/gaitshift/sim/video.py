"""Watching a run: an offscreen MP4 of the simulation and MuJoCo's passive viewer.

The video is rendered with ``mujoco.Renderer`` (headless OpenGL: set ``MUJOCO_GL=egl`` or ``osmesa``),
480 x 270 pixels, a free camera following the CoM from the side, and written with imageio's ffmpeg
(H.264) through an atomic rename.
"""

from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from gaitshift.common.atomic import atomic_path
from gaitshift.errors import InputError


class VideoRecorder:
    """Frames of a run at ``fps`` Hz of simulated time, written to ``path`` (.mp4) by :meth:`close`.

    ``wall`` accumulates the wall-clock seconds spent rendering (left out of the real-time factor).

    Raises:
        InputError: no OpenGL context can be created.
    """

    def __init__(self, model: mujoco.MjModel, path: str, fps: int) -> None:
        try:
            self.renderer = mujoco.Renderer(model, height=270, width=480)
        except Exception as exc:
            raise InputError("video", "render", f"an OpenGL context (set MUJOCO_GL=egl or osmesa): {exc}") from None
        self.path = Path(path)
        self.fps = fps
        self.frames: list[np.ndarray] = []
        self.next_frame = 0.0
        self.wall = 0.0

    def capture(self, t: float, d: mujoco.MjData, com: np.ndarray) -> None:
        """Render a frame if simulated time ``t`` (s) has reached the next frame time; the camera
        looks at the CoM ``com`` (3,)."""
        if t < self.next_frame:
            return
        r0 = time.perf_counter()
        cam = mujoco.MjvCamera()
        cam.type = mujoco.mjtCamera.mjCAMERA_FREE
        cam.lookat[:] = [com[0], com[1], 0.6]
        cam.distance = 2.8
        cam.azimuth = 120.0
        cam.elevation = -15.0
        self.renderer.update_scene(d, camera=cam)
        self.frames.append(self.renderer.render().copy())
        self.next_frame += 1.0 / self.fps
        self.wall += time.perf_counter() - r0

    def close(self) -> None:
        """Write the MP4 (if any frame was captured)."""
        if self.frames:
            write_mp4(self.path, self.frames, self.fps)


def write_mp4(path: Path, frames: list[np.ndarray], fps: int) -> None:
    """Write RGB frames (H, W, 3) uint8 to ``path`` as H.264, atomically."""
    import imageio.v2 as imageio

    with atomic_path(path) as tmp:
        w: Any = imageio.get_writer(str(tmp), fps=fps, format="FFMPEG", codec="libx264", macro_block_size=1)
        with w:
            for f in frames:
                w.append_data(f)


def open_viewer(m: mujoco.MjModel, d: mujoco.MjData) -> Any:
    """MuJoCo's passive viewer on ``d`` (call ``sync()`` after each step, ``close()`` at the end).

    Raises:
        InputError: no graphical display.
    """
    if not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY"):
        raise InputError("viewer", "no display", "a graphical display (DISPLAY or WAYLAND_DISPLAY set)")
    import threading

    import mujoco.viewer

    before = set(threading.enumerate())
    viewer = mujoco.viewer.launch_passive(m, d)
    viewer.gaitshift_threads = [t for t in threading.enumerate() if t not in before]
    return viewer


def close_viewer(viewer: Any, timeout: float = 5.0) -> None:
    """Close the passive viewer and join (up to ``timeout`` s) its render thread: the process must not
    tear GLFW down at exit while that thread still draws or destroys its window (a segfault)."""
    viewer.close()
    for thread in getattr(viewer, "gaitshift_threads", []):
        thread.join(timeout)
