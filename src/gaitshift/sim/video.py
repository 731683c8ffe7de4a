"""Watching a run: an offscreen MP4 of the simulation and MuJoCo's passive viewer.

The video is rendered with ``mujoco.Renderer`` (headless OpenGL: set ``MUJOCO_GL=egl`` or ``osmesa``)
at ``size`` pixels (default 1280 x 720, :data:`VIDEO_SIZE`) and ``fps`` frames per second of simulated
time, and streamed frame by frame to the ffmpeg binary of imageio-ffmpeg (H.264, yuv420p) into a
temporary file that :meth:`VideoRecorder.close` renames onto the target (``discard`` removes it). The camera is MuJoCo's
tracking camera on the floating base (``mjCAMERA_TRACKING``: it keeps the base's subtree CoM at the
centre, from the side and a little above, at a distance of 4 x the robot's CoM height). Drawn over the
scene (decorative geoms appended to the renderer's ``MjvScene`` after ``update_scene``): every planned
foothold as a flat sole-sized box (blue left, orange right), the planned CoM path as a thin green
line, and the CoM path the robot actually took so far as a red line with a red ball at the CoM.
"""

from __future__ import annotations

import contextlib
import itertools
import os
import re
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from gaitshift.common.atomic import atomic_path
from gaitshift.errors import InputError

#: default video size (width, height), pixels
VIDEO_SIZE = (1280, 720)
#: largest video size, pixels
MAX_SIZE = (3840, 2160)
FOOT_RGBA = (np.array([0.15, 0.45, 0.95, 0.9], np.float32), np.array([0.95, 0.55, 0.1, 0.9], np.float32))
PLAN_RGBA = np.array([0.1, 0.6, 0.25, 0.9], np.float32)
COM_RGBA = np.array([0.9, 0.1, 0.1, 1.0], np.float32)


def parse_video_size(text: str, field: str = "--video-size") -> tuple[int, int]:
    """``"1280x720"`` -> (1280, 720), checked by :func:`check_video`.

    Raises:
        InputError: not ``WxH`` with even sizes within :data:`MAX_SIZE`.
    """
    match = re.fullmatch(r"\s*(\d{1,5})\s*[xX]\s*(\d{1,5})\s*", str(text))
    if match is None:
        raise InputError(field, text, "WIDTHxHEIGHT in pixels, e.g. 1280x720")
    size = (int(match.group(1)), int(match.group(2)))
    check_video(size, 30, field)
    return size


def check_video(size: tuple[int, int], fps: int, size_field: str = "video_size", fps_field: str = "video_fps") -> None:
    """Even width and height in [16, MAX_SIZE] pixels and an integer frame rate in [1, 240] Hz.

    Raises:
        InputError: naming the field at fault.
    """
    w, h = size
    if w % 2 or h % 2 or not (16 <= w <= MAX_SIZE[0] and 16 <= h <= MAX_SIZE[1]):
        raise InputError(size_field, f"{w}x{h}", f"even width 16..{MAX_SIZE[0]} and height 16..{MAX_SIZE[1]} pixels")
    if isinstance(fps, bool) or not isinstance(fps, int) or not 1 <= fps <= 240:
        raise InputError(fps_field, fps, "an integer frame rate in [1, 240] Hz")


@dataclass(frozen=True)
class Overlay:
    """What is drawn over the scene: ``footsteps`` (M, 4: x, y, z, yaw) and ``sides`` (M,: 0 left,
    1 right) with the sole ``size`` (length, width, m), and the planned CoM path ``com_path`` (K, 3)."""

    footsteps: np.ndarray
    sides: np.ndarray
    size: tuple[float, float]
    com_path: np.ndarray


class VideoRecorder:
    """Frames of a run at ``fps`` Hz of simulated time, written to ``path`` (.mp4) by :meth:`close`.

    ``size``: (width, height) pixels; ``track``: body id the camera follows (None: a free camera at
    the CoM); ``height``: the robot's CoM height, m (sets the camera distance); ``overlay``: the plan
    drawn over the scene. ``wall`` accumulates the wall-clock seconds spent rendering (left out of
    the real-time factor).

    Raises:
        InputError: bad size or rate, or no OpenGL context can be created.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        path: str,
        fps: int,
        size: tuple[int, int] = VIDEO_SIZE,
        track: int | None = None,
        height: float = 0.7,
        overlay: Overlay | None = None,
    ) -> None:
        check_video(size, fps)
        width, rows = size
        model.vis.global_.offwidth = max(int(model.vis.global_.offwidth), width)
        model.vis.global_.offheight = max(int(model.vis.global_.offheight), rows)
        try:
            self.renderer = mujoco.Renderer(model, height=rows, width=width)
        except Exception as exc:
            raise InputError("video", "render", f"an OpenGL context (set MUJOCO_GL=egl or osmesa): {exc}") from None
        self.renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = 0  # 5x faster with software GL
        self.renderer.scene.flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = 0
        self.path = Path(path)
        self.fps, self.size = fps, size
        self.n_frames = 0
        self.output = contextlib.ExitStack()
        self.writer: Any = None
        self.next_frame = 0.0
        self.wall = 0.0
        self.overlay = overlay
        self.trail: list[np.ndarray] = []
        self.cam = mujoco.MjvCamera()
        if track is not None:
            self.cam.type = mujoco.mjtCamera.mjCAMERA_TRACKING
            self.cam.trackbodyid = track
        else:
            self.cam.type = mujoco.mjtCamera.mjCAMERA_FREE
        self.cam.distance = 4.0 * height
        self.cam.azimuth = 120.0
        self.cam.elevation = -15.0

    def capture(self, t: float, d: mujoco.MjData, com: np.ndarray) -> None:
        """Render a frame if simulated time ``t`` (s) has reached the next frame time; ``com`` (3,) is
        the CoM (the end of the drawn path, and the camera's target without tracking)."""
        if t < self.next_frame:
            return
        r0 = time.perf_counter()
        self.trail.append(np.array(com, float))
        if self.cam.type == mujoco.mjtCamera.mjCAMERA_FREE:
            self.cam.lookat[:] = [com[0], com[1], com[2] * 0.8]
        self.renderer.update_scene(d, camera=self.cam)
        self._draw(self.renderer.scene)
        self._write(self.renderer.render())
        self.next_frame += 1.0 / self.fps
        self.wall += time.perf_counter() - r0

    def _draw(self, scene: mujoco.MjvScene) -> None:
        eye = np.eye(3).ravel()
        if self.overlay is not None:
            length, width = self.overlay.size
            for (x, y, z, yaw), side in zip(self.overlay.footsteps, self.overlay.sides, strict=True):
                c, s = np.cos(yaw), np.sin(yaw)
                mat = np.array([c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0])
                box = [length / 2, width / 2, 0.001]
                _add(scene, mujoco.mjtGeom.mjGEOM_BOX, box, [x, y, z + 0.002], mat, FOOT_RGBA[int(side)])
            _path(scene, self.overlay.com_path, 2.0, PLAN_RGBA)
        _path(scene, np.array(self.trail[-2000:]), 4.0, COM_RGBA)
        _add(scene, mujoco.mjtGeom.mjGEOM_SPHERE, [0.03, 0, 0], self.trail[-1], eye, COM_RGBA)

    def _write(self, frame: np.ndarray) -> None:
        """Send one RGB frame (H, W, 3) uint8 to ffmpeg (started at the first frame)."""
        if self.writer is None:
            import imageio_ffmpeg

            tmp = self.output.enter_context(atomic_path(self.path, "--video"))
            self.writer = imageio_ffmpeg.write_frames(
                str(tmp), self.size, fps=self.fps, codec="libx264", pix_fmt_out="yuv420p", quality=7,
                macro_block_size=2, ffmpeg_log_level="error",
            )  # fmt: skip
            self.writer.send(None)
        self.writer.send(np.ascontiguousarray(frame).tobytes())
        self.n_frames += 1

    def close(self) -> None:
        """Finish the MP4 (if any frame was captured) and rename it onto ``path``."""
        if self.writer is not None:
            self.writer.close()
            self.writer = None
        self.output.close()
        self.renderer.close()

    def discard(self) -> None:
        """Stop without a file: the temporary file is removed (the run failed); after :meth:`close`,
        nothing happens."""
        if self.writer is not None:
            self.writer.close()
            self.writer = None
            with contextlib.suppress(RuntimeError):
                self.output.__exit__(RuntimeError, RuntimeError("video discarded"), None)
            self.renderer.close()


def _add(scene: mujoco.MjvScene, gtype: int, size: Any, pos: Any, mat: Any, rgba: Any) -> mujoco.MjvGeom | None:
    """Append one decorative geom to ``scene`` (dropped when the scene is full)."""
    if scene.ngeom >= scene.maxgeom:
        return None
    g = scene.geoms[scene.ngeom]
    mujoco.mjv_initGeom(g, gtype, np.asarray(size, float), np.asarray(pos, float), np.asarray(mat, float), rgba)
    scene.ngeom += 1
    return g


def _path(scene: mujoco.MjvScene, points: np.ndarray, width: float, rgba: np.ndarray) -> None:
    """A polyline through ``points`` (K, 3), ``width`` pixels wide (line geoms: no tessellation)."""
    for a, b in itertools.pairwise(points):
        if np.linalg.norm(b - a) < 1e-6:
            continue
        g = _add(scene, mujoco.mjtGeom.mjGEOM_LINE, [0, 0, 0], [0, 0, 0], np.eye(3).ravel(), rgba)
        if g is not None:
            mujoco.mjv_connector(g, mujoco.mjtGeom.mjGEOM_LINE, width, a, b)


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


def video_overlay(traj: Any, sole_size: tuple[float, float], step: float = 0.02) -> Overlay:
    """The plan drawn over a video: its footholds and its CoM path sampled every ``step`` s."""
    k = max(1, round(step / traj.dt))
    return Overlay(traj.footsteps, traj.footstep_side, (float(sole_size[0]), float(sole_size[1])), traj.com_pos[::k])
