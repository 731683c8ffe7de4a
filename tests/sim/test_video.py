"""Watching a run: the MP4 of the simulation decodes (imageio's ffmpeg reader) with one frame per
1/fps of simulated time and shows the robot; the viewer needs a display."""

from __future__ import annotations

import imageio
import mujoco
import numpy as np
import pytest

from gaitshift.errors import InputError
from gaitshift.sim.plant import build_plant
from gaitshift.sim.video import VideoRecorder, open_viewer
from standing import standing


def test_video_has_one_frame_per_period_and_shows_the_robot(tmp_path):
    plant, d, _, _ = standing()
    m = plant.model
    rec = VideoRecorder(m, str(tmp_path / "run.mp4"), fps=25)
    for k in range(100):  # 0.2 s: frames at 0, 0.04, ..., 0.16 s
        rec.capture(k * 0.002, d, d.subtree_com[0])
    rec.close()
    with imageio.get_reader(str(tmp_path / "run.mp4"), format="FFMPEG") as r:
        frames = np.array(list(iter(r)))  # iter: the reader reports an infinite length
    assert frames.shape == (5, 270, 480, 3)
    centre = frames[0, 60:210, 180:300].astype(float).mean(axis=2)
    assert frames[0].astype(float).std() > 5.0 and np.mean(centre > 110) > 0.02  # the light-grey robot
    assert rec.wall > 0.0


def test_viewer_without_a_display_is_an_input_error(monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    m = build_plant(0.002).model
    with pytest.raises(InputError, match="display"):
        open_viewer(m, mujoco.MjData(m))
