"""``gaitshift teleop --sim`` drives the closed-loop G1 live: a key script (no keyboard) walks it,
turns it and stops it without a fall, prints the status line and writes the simulation log; with a
display (a real virtual X server, Debian's Xvfb) the MuJoCo viewer opens on the same loop."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

EXE = str(Path(sys.executable).parent / "gaitshift")
SCRIPT = "up up up wait=1.5 turn-left wait=1.5 turn-right wait=0.5 quit"


def _run(args, env, timeout=600):
    return subprocess.run(
        [EXE, "teleop", "--sim", *args], env=env, capture_output=True, text=True, timeout=timeout, check=False
    )


def test_teleop_sim_script_walks_turns_and_stops_without_a_fall(tmp_path):
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    out = tmp_path / "tel.npz"
    r = _run(["--script", SCRIPT, "--no-realtime", "--out", str(out)], env)
    assert r.returncode == 0, r.stderr
    assert "status line" in r.stdout and "walk" in r.stdout and "real-time factor" in r.stdout
    with np.load(out) as z:
        assert not bool(z["fell"])
        q = z["qpos"]
    yaw = np.arctan2(2 * (q[:, 3] * q[:, 6] + q[:, 4] * q[:, 5]), 1 - 2 * (q[:, 5] ** 2 + q[:, 6] ** 2))
    assert np.ptp(yaw) > 0.1  # it turned
    assert q[-1, 0] - q[0, 0] > 0.3  # it walked forward


def test_teleop_sim_viewer_opens_under_xvfb(tmp_path):
    xvfb = shutil.which("Xvfb")
    assert xvfb is not None, "Xvfb is installed by .ci/system-deps (make test)"
    display = f":{90 + os.getpid() % 50}"
    server = subprocess.Popen(
        [xvfb, display, "-screen", "0", "640x480x24", "-nolisten", "tcp"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        time.sleep(1.5)
        assert server.poll() is None, "Xvfb did not start"
        env = dict(os.environ, DISPLAY=display)
        # standing half a second, then quit: the viewer on the loop (the passive viewer's render thread,
        # software GL on Xvfb, took half the CPU and doubled the run when it walked a step)
        r = _run(["--viewer", "--script", "wait=0.5 quit", "--no-realtime", "--out", str(tmp_path / "v.npz")], env)
        assert r.returncode == 0, r.stderr
        assert "MuJoCo viewer" in r.stdout
        with np.load(tmp_path / "v.npz") as z:  # the quit while standing ends the run: rest, half a second
            assert float(z["t"][-1]) < 1.5
    finally:
        server.terminate()
        server.wait(timeout=10)


def test_viewer_without_a_display_is_one_line_and_exit_2(tmp_path):
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    r = _run(["--viewer", "--script", "quit", "--out", str(tmp_path / "x.npz")], env, timeout=120)
    assert r.returncode == 2
    assert r.stderr.count("\n") == 1 and "--viewer" in r.stderr
    assert not (tmp_path / "x.npz").exists()


@pytest.mark.parametrize("bad", ["spin", "wait=-1"])
def test_bad_tokens_are_one_line_errors(tmp_path, bad):
    r = _run(["--script", bad, "--out", str(tmp_path / "x.npz")], dict(os.environ), timeout=120)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "--script" in r.stderr
