"""Offscreen video of the whole-body motion: the MP4 decodes (imageio's ffmpeg reader) and shows the
robot (bright pixels that vanish when the robot is moved under the floor), also through the osmesa
fallback and the ``animate`` command."""

from __future__ import annotations

import imageio
import numpy as np
import pytest

import gaitshift
from gaitshift.trajectory.contract import Trajectory
from gaitshift.wholebody.ik import wholebody
from gaitshift.wholebody.joints import JointTrajectory, subsample
from gaitshift.wholebody.render import render_video

RATE = 100.0


@pytest.fixture(scope="module")
def short_motion(tmp_path_factory):
    """The first 1.6 s of the G1 walk-run-walk (start, first steps), IK at 100 Hz."""
    full = gaitshift.plan(gaitshift.load_scenario("g1-walk-run-walk"))
    traj = subsample(full, RATE)
    n = int(1.6 * RATE)
    arrays = {k: (v[:n] if np.ndim(v) and len(v) == len(traj) else v) for k, v in traj.arrays().items()}
    arrays["footsteps"], arrays["footstep_side"] = traj.footsteps, traj.footstep_side
    short = Trajectory.from_arrays(arrays, dict(traj.meta))
    joints = wholebody(short, "g1")
    folder = tmp_path_factory.mktemp("render")
    short.save(folder / "plan.npz")
    joints.save(folder / "joints.npz")
    return short, joints, folder


def _frames(path):
    with imageio.get_reader(str(path), format="FFMPEG") as r:
        return np.array(list(iter(r)))  # iter: the reader reports an infinite length


def test_mp4_decodes_and_shows_the_moving_robot(short_motion):
    traj, joints, folder = short_motion
    out = render_video(joints, folder / "motion.mp4", robot="g1", traj=traj, fps=10, width=160, height=96)
    frames = _frames(out)
    assert frames.shape[1:] == (96, 160, 3)
    assert abs(len(frames) - 16) <= 1
    first = frames[0].astype(float)
    # not blank: the image has structure, and the light-grey robot fills part of the centre
    assert first.std() > 5.0
    centre = first[16:80, 50:110].mean(axis=2)
    assert np.mean(centre > 110) > 0.02
    # the robot moves: the last frame differs from the first
    assert np.abs(frames[-1].astype(float) - first).mean() > 1.0


def test_robot_pixels_come_from_the_model_not_the_overlay(short_motion):
    """Moving the robot 50 m under the floor removes the bright body from the same frame."""
    _, joints, folder = short_motion
    head = JointTrajectory(joints.t[:5], joints.qpos[:5].copy(), joints.qvel[:5], dict(joints.meta))
    sunk = JointTrajectory(head.t, head.qpos.copy(), head.qvel, head.meta)
    sunk.qpos[:, 2] -= 50.0
    centre = []
    for name, jt in (("shown", head), ("sunk", sunk)):
        out = render_video(jt, folder / f"{name}.mp4", robot="g1", traj=None, fps=10, width=160, height=96)
        centre.append(_frames(out)[0].astype(float).mean(axis=2)[16:80, 50:110])
    shown, empty = centre
    assert np.mean(empty > 110) < 0.01
    assert np.mean(shown > 110) > 0.02


def test_cli_animate_writes_an_mp4_and_rejects_other_suffixes(short_motion, capsys):
    from gaitshift.cli import main

    _, _, folder = short_motion
    out = folder / "cli.mp4"
    with pytest.raises(SystemExit) as ex:
        main(
            [
                "animate",
                str(folder / "plan.npz"),
                "--robot",
                "g1",
                "--out",
                str(out),
                "--joints",
                str(folder / "joints.npz"),
                "--fps",
                "5",
                "--width",
                "128",
                "--height",
                "96",
            ]
        )
    assert ex.value.code == 0
    assert len(_frames(out)) >= 7
    with pytest.raises(SystemExit) as ex:
        main(["animate", str(folder / "plan.npz"), "--out", str(folder / "x.gif")])
    assert ex.value.code == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1


def test_falls_back_to_osmesa_when_egl_cannot_start(tmp_path):
    """PyOpenGL pinned to osmesa makes the EGL context fail: the video still comes out (osmesa child)."""
    import subprocess
    import sys

    script = tmp_path / "render.py"
    out = tmp_path / "fallback.mp4"
    script.write_text(
        "import mujoco, numpy as np\n"
        "from gaitshift.robots import load_robot\n"
        "from gaitshift.wholebody.joints import JointTrajectory\n"
        "from gaitshift.wholebody.render import render_video\n"
        "r = load_robot('g1'); m = r.model(); d = mujoco.MjData(m)\n"
        "q = r.standing_qpos(m); d.qpos[:] = q; mujoco.mj_kinematics(m, d)\n"
        "q[2] -= d.site('gaitshift_left_sole').xpos[2]\n"
        "qs = np.tile(q, (4, 1)); qs[:, 0] += np.linspace(0, 0.2, 4)\n"
        "j = JointTrajectory(np.arange(4) * 0.1, qs, np.zeros((4, m.nv)), {'robot': 'g1'})\n"
        f"render_video(j, {str(out)!r}, fps=10, width=96, height=64)\n"
    )
    env = dict(__import__("os").environ, MUJOCO_GL="egl", PYOPENGL_PLATFORM="osmesa")
    proc = subprocess.run(
        [sys.executable, str(script)], env=env, capture_output=True, text=True, timeout=300, check=False
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    frames = _frames(out)
    assert len(frames) >= 3 and frames[0].astype(float).std() > 5.0
