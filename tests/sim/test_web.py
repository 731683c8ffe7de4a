"""The browser view of a live session (``gaitshift teleop --sim --web``) in a real browser: Debian's
Chromium (``/usr/bin/chromium``, installed by ``.ci/system-deps``), headless, driven by playwright.
Moving the page's vx slider changes the command of the running simulation: the page shows the new
command read back from the plan the simulation tracks, the simulation's own status line reports it,
and the robot then walks forward in the written log (its pelvis moves > 0.15 m in x and its
CoM speed reaches half the command). *End run* stops it at rest and ends the process with exit 0.

Also: the centre of pressure the view draws as the ZMP is, for a box resting on the floor, the
box's centre projected on the floor (statics: the floor's normal forces balance the weight about
the CoM); the plain-viser scene poses every moving body where MuJoCo's kinematics puts it, and
both shift the scene by minus the pelvis position."""

from __future__ import annotations

import os
import re
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import mujoco
import numpy as np
import pytest

from browser_pages import headless_chromium, open_page

EXE = str(Path(sys.executable).parent / "gaitshift")


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


class _Proc:
    """A subprocess whose stdout lines are collected by a thread."""

    def __init__(self, args: list[str]) -> None:
        env = dict(os.environ, PYTHONUNBUFFERED="1")
        self.p = subprocess.Popen(
            args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, text=True, env=env
        )
        self.lines: list[str] = []
        self.err: list[str] = []
        threading.Thread(target=lambda: self.lines.extend(self.p.stdout), daemon=True).start()  # type: ignore[arg-type]
        threading.Thread(target=lambda: self.err.extend(self.p.stderr), daemon=True).start()  # type: ignore[arg-type]

    def wait_line(self, pattern: str, timeout: float) -> re.Match[str]:
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            for line in list(self.lines):
                m = re.search(pattern, line)
                if m:
                    return m
            assert self.p.poll() is None, f"exited {self.p.returncode}: {''.join(self.lines + self.err)[-2000:]}"
            time.sleep(0.1)
        raise AssertionError(f"no line matching {pattern!r}: {''.join(self.lines)[-2000:]}")


def test_browser_slider_changes_the_command_of_the_running_simulation(tmp_path):
    """Chromium moves vx: page, sim status line and the logged motion all follow."""
    out = tmp_path / "web.npz"
    port = _free_port()
    proc = _Proc([EXE, "teleop", "--sim", "--web", "--web-port", str(port), "--max-time", "120", "--out", str(out)])
    try:
        with headless_chromium() as browser:
            url = proc.wait_line(r"web view: (http://\S+)", 60).group(1)
            page = open_page(browser, url)  # its 3D canvas hidden (test_scene_poses_... checks the scene)
            page.get_by_text("commanded: vx = +0.00").wait_for(timeout=90_000)
            slider = page.get_by_role("slider").first  # vx
            box = slider.locator("xpath=..").bounding_box()
            assert box is not None
            lo, hi = float(slider.get_attribute("aria-valuemin")), float(slider.get_attribute("aria-valuemax"))
            page.mouse.click(box["x"] + box["width"] * (0.3 - lo) / (hi - lo), box["y"] + box["height"] / 2)
            page.wait_for_function(
                "s => Number(s.getAttribute('aria-valuenow')) > 0.1", arg=slider.element_handle(), timeout=90_000
            )
            vx = float(slider.get_attribute("aria-valuenow"))
            assert 0.1 < vx < 0.6, vx
            # the simulation side: its status line, then the plan it tracks (shown on the page)
            proc.wait_line(r"web\s+t=\s*\S+ s\s+command=\(" + re.escape(f"{vx:+.2f}, +0.00 m/s"), 90)
            page.get_by_text(f"commanded: vx = {vx:+.2f} m/s").wait_for(timeout=90_000)
            page.screenshot(path=str(tmp_path / "web_view.png"))
            proc.wait_line(r"walk\s+speed=\(\+0\.[1-9]", 90)  # the measured speed follows
            page.get_by_role("button", name="End run").click(timeout=120_000)  # a starved browser is slow, not wrong
        assert proc.p.wait(timeout=60) == 0, "".join(proc.err)[-2000:]
    finally:
        if proc.p.poll() is None:
            proc.p.kill()
            proc.p.wait()
    assert any(re.search(r"quit\s+t=", line) for line in proc.lines)
    with np.load(out) as z:
        assert not bool(z["fell"])
        q, v, t = z["qpos"], z["com_vel"], z["t"]
    assert q[-1, 0] - q[0, 0] > 0.15  # it walked forward
    # the measured CoM speed, averaged over 1 s windows (a stride), reaches half the command
    n = round(1.0 / float(t[1] - t[0]))
    assert np.convolve(v[:, 0], np.ones(n) / n, "valid").max() > 0.5 * vx


def test_floor_cop_of_a_resting_box_is_its_centre():
    """Statics: for a box at rest on the floor the CoP is below its centre of mass."""
    from gaitshift.sim.web import floor_cop

    xml = """<mujoco><worldbody><geom name="floor" type="plane" size="5 5 .1"/>
      <body pos="0.3 -0.2 0.1"><freejoint/><geom type="box" size=".1 .05 .1" mass="2"/></body>
      </worldbody></mujoco>"""
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    for _ in range(1500):
        mujoco.mj_step(m, d)
    mujoco.mj_forward(m, d)
    cop = floor_cop(d, 0)
    assert cop is not None
    np.testing.assert_allclose(cop[:2], d.xpos[1, :2], atol=2e-3)
    assert abs(cop[2]) < 2e-3
    d.qpos[2] = 1.0  # lifted: no contact, no CoP
    mujoco.mj_forward(m, d)
    assert floor_cop(d, 0) is None


@pytest.mark.parametrize("backend", ["mjviser", "viser"])
def test_scene_poses_every_moving_body_from_mjdata(backend):
    """Each body node sits at MuJoCo's world pose (x_b, q_b) (viser), the scene shifted by -x_pelvis."""
    import viser

    from gaitshift.sim.plant import build_plant
    from gaitshift.sim.web_scene import build_scene

    m = build_plant(0.002, "g1").model
    d = mujoco.MjData(m)
    d.qpos[:3] = [0.4, -0.3, 0.8]
    d.qpos[7:] = 0.1
    mujoco.mj_forward(m, d)
    server = viser.ViserServer(host="127.0.0.1", port=_free_port(), verbose=False)
    try:
        scene = build_scene(backend, server, m)
        scene.update(d)
        if backend == "viser":
            np.testing.assert_allclose(scene.frame.position, -d.xpos[scene.tracked])
            for b, node in scene.nodes:
                np.testing.assert_allclose(node.position, d.xpos[b], atol=1e-9)
                np.testing.assert_allclose(node.wxyz, d.xquat[b], atol=1e-9)
        else:  # mjviser keeps its mesh groups private: the scene shift is what is public
            np.testing.assert_allclose(scene.scene.fixed_bodies_frame.position, -d.xpos[1])
    finally:
        server.stop()


def test_the_view_draws_the_controllers_map_at_its_heights_its_edges_apart_and_its_last_scan():
    """A controller's map holding a 10 cm step: the page's map cloud has one point per seen cell at
    that cell's centre and height, coloured by height; the cells on the step's edge are a red cloud of
    their own; the perceiver's last scan (its points as the controller placed them) is a cloud after
    the first tick and is redrawn only when the perceiver has fused a new frame."""
    from types import SimpleNamespace

    from gaitshift.api import plan
    from gaitshift.control.perception import EDGE_COLOR, ElevationMap, MapSettings
    from gaitshift.sim.plant import build_plant
    from gaitshift.sim.web import WebView

    emap = ElevationMap(MapSettings(size=1.0, resolution=0.05))
    emap.recenter(np.zeros(2))
    xy = emap.centres().reshape(-1, 2)
    z = np.where(xy[:, 0] > 0.2, 0.1, 0.0)
    emap.fuse(np.column_stack([xy, z]), np.full(len(z), 1e-6))
    scan = np.random.default_rng(0).uniform(-1.0, 1.0, (700, 3))
    perceiver = SimpleNamespace(map=emap, scan=scan, frames=1)
    traj = plan("g1-walk")
    m = build_plant(0.002, "g1").model
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    view = WebView(lambda: traj, port=_free_port())
    try:
        view.attach(SimpleNamespace(perceiver=perceiver))
        view(0, 0.0, d)
        pts, cols = view.nodes["map"].points, view.nodes["map"].colors
        assert len(pts) == emap.n**2
        np.testing.assert_allclose(pts[:, 2], np.where(pts[:, 0] > 0.2, 0.1, 0.0), atol=1e-5)
        assert not np.any(np.all(cols == EDGE_COLOR, axis=1))  # the surface: heights only
        edges = view.nodes["map_edges"]
        assert len(edges.points) == 2 * emap.n and np.all(np.abs(edges.points[:, 0] - 0.2) < 0.05)
        assert tuple(edges.colors) == EDGE_COLOR
        np.testing.assert_allclose(view.nodes["scan"].points, scan, atol=1e-6)  # float32
        perceiver.scan = scan[:10]
        view(1, 0.05, d)  # a frame is due, but no new scan was fused: the cloud stays
        assert len(view.nodes["scan"].points) == 700
        perceiver.frames = 2
        view(2, 0.1, d)
        np.testing.assert_allclose(view.nodes["scan"].points, scan[:10], atol=1e-6)
    finally:
        view.close()
