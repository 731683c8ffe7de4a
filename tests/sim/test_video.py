"""Watching a run: the MP4 of the simulation decodes (imageio's ffmpeg reader) with one frame per
1/fps of simulated time at the requested size (default 1280 x 720) and shows the robot; the tracking
camera keeps the robot in the middle of the picture wherever it walks; the planned footholds and the
CoM path are drawn over the scene; a bad size or rate is an InputError; a discarded video leaves no
file; the viewer needs a display."""

from __future__ import annotations

import imageio
import mujoco
import numpy as np
import pytest

from gaitshift.errors import InputError
from gaitshift.sim.plant import build_plant
from gaitshift.sim.video import Overlay, VideoRecorder, open_viewer, parse_video_size
from standing import standing

SMALL = (480, 270)


def frames_of(path):
    with imageio.get_reader(str(path), format="FFMPEG") as r:
        return np.array(list(iter(r)))  # iter: the reader reports an infinite length


def robot_centre(frame):
    """Column and row of the centroid of the robot's pixels (grey, but neither the uniform floor
    colour nor the black sky), as fractions of the width and height, and their share of the picture."""
    f = frame.astype(float)
    floor = np.median(f[-20:].reshape(-1, 3), axis=0)
    grey = (np.ptp(f, axis=2) < 25) & (f.mean(axis=2) > 12) & (np.abs(f - floor).max(axis=2) > 12)
    rows, cols = np.nonzero(grey)
    return cols.mean() / frame.shape[1], rows.mean() / frame.shape[0], grey.mean()


def test_video_has_one_frame_per_period_and_shows_the_robot(tmp_path):
    plant, d, _, _ = standing()
    rec = VideoRecorder(plant.model, str(tmp_path / "run.mp4"), fps=25, size=SMALL, track=plant.pelvis_body)
    for k in range(100):  # 0.2 s: frames at 0, 0.04, ..., 0.16 s
        rec.capture(k * 0.002, d, d.subtree_com[0])
    rec.close()
    frames = frames_of(tmp_path / "run.mp4")
    assert frames.shape == (5, 270, 480, 3)
    assert frames[0].astype(float).std() > 5.0 and robot_centre(frames[0])[2] > 0.02  # the grey robot
    assert rec.wall > 0.0
    assert [p.name for p in tmp_path.iterdir()] == ["run.mp4"]


def test_the_default_size_is_1280_by_720(tmp_path):
    plant, d, _, _ = standing()
    rec = VideoRecorder(plant.model, str(tmp_path / "run.mp4"), fps=30, track=plant.pelvis_body)
    rec.capture(0.0, d, d.subtree_com[0])
    rec.close()
    assert frames_of(tmp_path / "run.mp4").shape == (1, 720, 1280, 3)


def test_the_tracking_camera_keeps_the_robot_centred_and_the_overlay_is_drawn(tmp_path):
    plant, d, q0, feet = standing()
    m = plant.model
    steps = np.array([[x, y, 0.0, 0.0] for x in (0.0, 1.5, 3.0) for y in (feet[0, 1], feet[1, 1])])
    overlay = Overlay(steps, np.array([0, 1] * 3), (0.18, 0.07), np.array([[0, 0, 0.6], [3.0, 0, 0.6]]))
    rec = VideoRecorder(m, str(tmp_path / "walk.mp4"), 10, SMALL, plant.pelvis_body, 0.65, overlay)
    for k, x in enumerate((0.0, 3.0)):  # the robot moved 3 m forward between the frames
        d.qpos[:] = q0
        d.qpos[0] += x
        mujoco.mj_forward(m, d)
        rec.capture(k * 0.1, d, d.subtree_com[0])
    rec.close()
    frames = frames_of(tmp_path / "walk.mp4")
    (u0, v0, n0), (u1, v1, n1) = robot_centre(frames[0]), robot_centre(frames[1])
    assert abs(u0 - 0.5) < 0.1 and abs(u1 - 0.5) < 0.1 and abs(v1 - v0) < 0.05 and abs(n1 / n0 - 1) < 0.2
    f = frames[1].astype(int)
    blue = (f[..., 2] > 150) & (f[..., 2] - f[..., 0] > 60)  # left footholds
    orange = (f[..., 0] > 180) & (f[..., 0] - f[..., 2] > 80) & (f[..., 1] > 80)  # right footholds
    red = (f[..., 0] > 150) & (f[..., 1] < 70) & (f[..., 2] < 70)  # the CoM path and ball
    assert blue.sum() > 50 and orange.sum() > 50 and red.sum() > 50
    # a free camera that stays where the robot started loses it
    rec = VideoRecorder(m, str(tmp_path / "free.mp4"), 10, SMALL, None, 0.65)
    rec.capture(0.0, d, np.array([0.0, 0.0, 0.6]))
    rec.close()
    assert (
        robot_centre(frames_of(tmp_path / "free.mp4")[0])[0] < 0.4
        or robot_centre(frames_of(tmp_path / "free.mp4")[0])[0] > 0.6
    )


def test_a_discarded_video_leaves_no_file(tmp_path):
    plant, d, _, _ = standing()
    rec = VideoRecorder(plant.model, str(tmp_path / "run.mp4"), fps=25, size=SMALL)
    rec.capture(0.0, d, d.subtree_com[0])
    rec.discard()
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("text", ["1280x721", "15x16", "7680x4320", "big", "1280", "-2x4"])
def test_a_bad_size_is_an_input_error_naming_the_flag(text):
    with pytest.raises(InputError, match="--video-size"):
        parse_video_size(text)
    assert parse_video_size(" 640X360 ") == (640, 360)


def test_a_bad_rate_is_an_input_error(tmp_path):
    plant, _, _, _ = standing()
    for fps in (0, 241, 2.5):
        with pytest.raises(InputError, match="video_fps"):
            VideoRecorder(plant.model, str(tmp_path / "x.mp4"), fps=fps)  # type: ignore[arg-type]


def test_viewer_without_a_display_is_an_input_error(monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    m = build_plant(0.002).model
    with pytest.raises(InputError, match="display"):
        open_viewer(m, mujoco.MjData(m))
