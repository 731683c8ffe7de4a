"""Kinematic playback: an offscreen MP4 of joint trajectories with the plan drawn on top.

Headless OpenGL: ``MUJOCO_GL=egl`` (default), falling back to ``osmesa`` (software) when EGL cannot
create a context. PyOpenGL binds one platform per process, so the fallback renders in a child
process. Shadows and reflections are off for speed. Frames go to the ffmpeg binary bundled with
imageio-ffmpeg (H.264, yuv420p).

Drawn on each frame: the planned CoM (red sphere, often inside the pelvis) with its ground projection
(red disc) and the trail of the last 1.5 s (small red dots), the planned ZMP (green disc; none in
flight), and every footstep as a flat sole-sized rectangle (blue left, orange right). The camera
follows the CoM from the side.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.common.atomic import atomic_path
from gaitshift.common.rotations import rot_z
from gaitshift.errors import InputError
from gaitshift.robots.config import RobotConfig, load_robot
from gaitshift.trajectory.contract import Trajectory

BACKENDS = ("egl", "osmesa")


class GLUnavailable(RuntimeError):
    """No headless OpenGL context could be created with this backend."""


def _context(backend: str, width: int, height: int) -> Any:
    try:
        if backend == "egl":
            from mujoco.egl import GLContext
        elif backend == "osmesa":
            from mujoco.osmesa import GLContext
        else:
            raise GLUnavailable(f"unknown MUJOCO_GL backend {backend!r}")
        ctx = GLContext(width, height)
        ctx.make_current()
        return ctx
    except GLUnavailable:
        raise
    except Exception as exc:  # missing library, no device, wrong PYOPENGL_PLATFORM
        raise GLUnavailable(f"{backend}: {type(exc).__name__}: {exc}") from None


def frame_indices(t: np.ndarray, fps: float) -> np.ndarray:
    """Sample index shown in each video frame: the last sample at or before k/fps."""
    times = np.arange(0.0, t[-1] - t[0] + 1e-9, 1.0 / fps) + t[0]
    idx: np.ndarray = np.clip(np.searchsorted(t, times + 1e-9, side="right") - 1, 0, len(t) - 1)
    return idx


FOOT_RGBA = (np.array([0.15, 0.45, 0.95, 0.55], np.float32), np.array([0.95, 0.55, 0.1, 0.55], np.float32))
COM_RGBA = np.array([0.9, 0.1, 0.1, 1.0], np.float32)
TRAIL_RGBA = np.array([0.9, 0.2, 0.2, 0.8], np.float32)
ZMP_RGBA = np.array([0.1, 0.85, 0.2, 1.0], np.float32)


class _Overlay:
    """The plan drawn into an ``MjvScene``: footsteps, CoM with its shadow and trail, ZMP."""

    def __init__(self, scene: Any, robot: RobotConfig, traj: Trajectory | None, t: np.ndarray) -> None:
        import mujoco

        self.mujoco, self.scene, self.traj = mujoco, scene, traj
        self.sole = robot.sole_size
        self.steps = traj.footsteps if traj is not None else np.zeros((0, 4))
        self.sides = traj.footstep_side if traj is not None else np.zeros(0, dtype=int)
        dt = float(t[1] - t[0]) if len(t) > 1 else 1.0
        self.trail, self.trail_step = round(1.5 / dt), max(1, round(0.05 / dt))

    def add(self, gtype: int, size: Any, pos: Any, mat: Any, rgba: Any) -> None:
        """Append one decorative geom (dropped when the scene is full)."""
        scene = self.scene
        if scene.ngeom >= scene.maxgeom:
            return
        g = scene.geoms[scene.ngeom]
        self.mujoco.mjv_initGeom(
            g,
            gtype,
            np.asarray(size, float),
            np.asarray(pos, float),
            np.asarray(mat, float),
            np.asarray(rgba, np.float32),
        )
        scene.ngeom += 1

    def draw(self, k: int, com: np.ndarray) -> None:
        """Draw the overlay of sample ``k`` with the CoM at ``com`` (3,)."""
        geom = self.mujoco.mjtGeom
        eye = np.eye(3).ravel()
        length, width = self.sole
        for (x, y, z, yaw), side in zip(self.steps, self.sides, strict=True):
            box = [length / 2, width / 2, 0.001]
            self.add(geom.mjGEOM_BOX, box, [x, y, z + 0.001], rot_z(yaw).ravel(), FOOT_RGBA[int(side)])
        self.add(geom.mjGEOM_SPHERE, [0.035, 0, 0], com, eye, COM_RGBA)
        self.add(geom.mjGEOM_CYLINDER, [0.03, 0.002, 0], [com[0], com[1], 0.004], eye, COM_RGBA)
        if self.traj is None:
            return
        for c in self.traj.com_pos[max(0, k - self.trail) : k + 1 : self.trail_step]:
            self.add(geom.mjGEOM_CYLINDER, [0.014, 0.002, 0], [c[0], c[1], 0.003], eye, TRAIL_RGBA)
        if np.all(np.isfinite(self.traj.zmp[k])):
            self.add(geom.mjGEOM_CYLINDER, [0.025, 0.002, 0], self.traj.zmp[k] + [0, 0, 0.006], eye, ZMP_RGBA)


def _render_frames(
    robot: RobotConfig,
    traj: Trajectory | None,
    qpos: np.ndarray,
    t: np.ndarray,
    out: Path,
    fps: float,
    width: int,
    height: int,
    backend: str,
) -> int:
    import imageio_ffmpeg
    import mujoco

    model = robot.model(scene=True)
    data = mujoco.MjData(model)
    ctx = _context(backend, width, height)
    con = None
    try:
        con = mujoco.MjrContext(model, mujoco.mjtFontScale.mjFONTSCALE_100)
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, con)
        scene = mujoco.MjvScene(model, maxgeom=4000)
        scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = 0
        scene.flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = 0
        opt = mujoco.MjvOption()
        cam = mujoco.MjvCamera()
        cam.type = mujoco.mjtCamera.mjCAMERA_FREE
        cam.distance = 3.2 * robot.com_height / 0.65
        cam.azimuth = 120.0
        cam.elevation = -20.0
        viewport = mujoco.MjrRect(0, 0, width, height)
        rgb = np.empty((height, width, 3), dtype=np.uint8)
        idx = frame_indices(t, fps)
        overlay = _Overlay(scene, robot, traj, t)
        writer = imageio_ffmpeg.write_frames(
            str(out),
            (width, height),
            fps=fps,
            codec="libx264",
            pix_fmt_out="yuv420p",
            quality=7,
            macro_block_size=2,
            ffmpeg_log_level="error",
        )
        writer.send(None)
        try:
            for k in idx:
                data.qpos[:] = qpos[k]
                mujoco.mj_kinematics(model, data)
                mujoco.mj_comPos(model, data)
                com = traj.com_pos[k] if traj is not None else data.subtree_com[1].copy()
                cam.lookat[:] = (com[0], com[1], 0.55 * robot.com_height)
                mujoco.mjv_updateScene(model, data, opt, None, cam, mujoco.mjtCatBit.mjCAT_ALL, scene)
                overlay.draw(k, com)
                mujoco.mjr_render(viewport, scene, con)
                mujoco.mjr_readPixels(rgb, None, viewport, con)
                writer.send(np.ascontiguousarray(rgb[::-1]).tobytes())
        finally:
            writer.close()
        return len(idx)
    finally:
        if con is not None:
            con.free()
        ctx.free()


def render_video(
    joints: Any,
    out: str | Path,
    robot: str | Path | RobotConfig | None = None,
    traj: Trajectory | None = None,
    fps: float = 30.0,
    width: int = 640,
    height: int = 360,
) -> Path:
    """Write an MP4 of ``joints`` (a :class:`~gaitshift.wholebody.joints.JointTrajectory`) to ``out``, atomically.

    Args:
        joints: joint trajectories (their ``meta['robot']`` names the robot unless ``robot`` is given).
        out: ``.mp4`` path.
        traj: the plan, for drawing CoM, ZMP and footsteps.
        fps, width, height: video rate (Hz) and size (pixels, even numbers).

    Raises:
        InputError: bad output name or size; GaitshiftError if no headless OpenGL backend works.
    """
    out = Path(out)
    if out.suffix.lower() != ".mp4":
        raise InputError("out", str(out), "a file ending in .mp4")
    check_video_options(fps, width, height)
    robot = load_robot(robot if robot is not None else joints.meta.get("robot", "g1"))
    requested = os.environ.get("MUJOCO_GL", "").lower()
    order = [requested] if requested in BACKENDS else []
    order += [b for b in BACKENDS if b not in order]
    errors = []
    with atomic_path(out) as tmp:
        for i, backend in enumerate(order):
            try:
                if i == 0:
                    _render_frames(robot, traj, joints.qpos, joints.t, tmp, fps, width, height, backend)
                else:
                    _render_in_child(robot, traj, joints, tmp, fps, width, height, backend)
                break
            except GLUnavailable as exc:
                errors.append(str(exc))
        else:
            from gaitshift.errors import GaitshiftError

            raise GaitshiftError(
                "no headless OpenGL backend works (" + "; ".join(errors) + "); run "
                ".ci/system-deps to install libegl1/libosmesa6"
            )
    return out


def check_video_options(fps: float, width: int, height: int) -> None:
    """The video's rate (Hz) and size (pixels), checked before any work.

    Raises:
        InputError: ``size`` not even width 16..1920 and height 16..1080, or ``fps`` not in (0, 240].
    """
    if width % 2 or height % 2 or not (16 <= width <= 1920 and 16 <= height <= 1080):
        raise InputError("size", f"{width}x{height}", "even width 16..1920 and height 16..1080 pixels")
    if not (0 < fps <= 240):
        raise InputError("fps", fps, "0 < fps <= 240")


def animate(
    source: Any,
    out: str | Path,
    robot: str | Path | RobotConfig = "g1",
    rate: float | None = 500.0,
    fps: float = 30.0,
    width: int = 640,
    height: int = 360,
    joints: Any = None,
) -> tuple[Path, Any]:
    """Plan (or load) ``source``, solve the whole-body IK for ``robot`` at ``rate`` Hz (unless ``joints``
    are given) and write the MP4. Returns (path, joints)."""
    from gaitshift.wholebody.ik import wholebody
    from gaitshift.wholebody.joints import load_plan, subsample

    check_video_options(fps, width, height)
    traj = load_plan(source)
    if joints is None:
        joints = wholebody(traj, robot, rate=rate)
        traj = subsample(traj, rate)
    else:
        dt_j = float(joints.t[1] - joints.t[0]) if len(joints.t) > 1 else traj.dt
        traj = subsample(traj, 1.0 / dt_j)
        if len(traj) != len(joints.t):
            raise InputError(
                "joints", f"{len(joints.t)} samples", f"the {len(traj)} samples of the plan at the joints' rate"
            )
    return render_video(joints, out, robot=robot, traj=traj, fps=fps, width=width, height=height), joints


def _render_in_child(
    robot: RobotConfig,
    traj: Trajectory | None,
    joints: Any,
    out: Path,
    fps: float,
    width: int,
    height: int,
    backend: str,
) -> None:
    """Render in a fresh interpreter whose PyOpenGL platform is ``backend``."""
    with tempfile.TemporaryDirectory(prefix="gaitshift-render-") as tmpdir:
        jpath = Path(tmpdir) / "joints.npz"
        np.savez(jpath, t=joints.t, qpos=joints.qpos)
        tpath = None
        if traj is not None:
            tpath = Path(tmpdir) / "plan.npz"
            traj.save(tpath)
        args = {
            "robot": robot.source,
            "joints": str(jpath),
            "plan": str(tpath) if tpath else None,
            "out": str(out),
            "fps": fps,
            "width": width,
            "height": height,
            "backend": backend,
        }
        env = dict(os.environ, MUJOCO_GL=backend, PYOPENGL_PLATFORM=backend)
        proc = subprocess.run(
            [sys.executable, "-m", "gaitshift.wholebody.render", json.dumps(args)],
            env=env,
            capture_output=True,
            text=True,
            check=False,
        )
        if proc.returncode == 3:
            raise GLUnavailable(proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else backend)
        if proc.returncode != 0:
            raise RuntimeError(f"render child failed: {proc.stderr.strip()[-2000:]}")


def _child_main(argv: list[str]) -> int:
    args = json.loads(argv[0])
    with np.load(args["joints"]) as z:
        t, qpos = z["t"], z["qpos"]
    traj = Trajectory.load(args["plan"]) if args["plan"] else None
    try:
        _render_frames(
            load_robot(args["robot"]),
            traj,
            qpos,
            t,
            Path(args["out"]),
            args["fps"],
            args["width"],
            args["height"],
            args["backend"],
        )
    except GLUnavailable as exc:
        print(str(exc), file=sys.stderr)
        return 3
    return 0


if __name__ == "__main__":  # pragma: no cover - exercised through the osmesa fallback
    sys.exit(_child_main(sys.argv[1:]))
