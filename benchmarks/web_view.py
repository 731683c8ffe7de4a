"""Measure the browser view (``gaitshift.sim.web``) with each scene builder: mjviser and plain viser.

One live G1 session per builder (locomotion generator, paced to the wall clock, 30 view frames per
simulated second) watched by Debian's headless Chromium (playwright, ``/usr/bin/chromium``, 1280 x
800): once the page shows the run, its vx slider is pressed 5 times (+0.05 m/s each, each press
waited for), the robot walks 3 s more, and the page's *End run* ends it. Measured:

- ``server_start_s``: ``ViserServer`` up (the page answers);
- ``first_frame_s``: first tick of the run (scene built there) -> the first status shown in the
  page's DOM (the scene was delivered before it and parsed by then; a script in the page records
  the time, same machine clock); ``first_status_t``: the simulated time that status showed;
- ``scene_bytes``: websocket bytes (as sent: viser compresses with zstd) received up to that first
  status message (the scene);
- ``bytes_per_frame``: websocket bytes received after it / frames drawn;
- ``update_wall_ms``: wall time of one frame update in the simulation thread, median and p95;
- ``cpu_ms_per_frame``: (process CPU time of the run - simulated s x CPU s per simulated s of a run
  without a view, walking at 0.2 m/s) / frames;
- ``frames_per_s``: frames drawn per wall-clock second (target 30 x real-time factor);
- ``view_latency_ms``: a status frame's send (after the flush) -> its text in the page's DOM, median, p95;
- ``command_latency_ms``: slider key press in the browser -> the command applied in the simulation
  thread, median, p95;
- ``rtf``: the run's real-time factor (``rtf_no_view`` without a view and without a browser).

``micro``: the scene update alone (no browser, no simulation), CPU ms per update over 300 random G1
poses, and the scene build time.

Usage: ``.venv/bin/python benchmarks/web_view.py [--screenshot docs/figures/web_view.png]``; prints
one JSON object (also written to ``benchmarks/web_view.json``).
"""

from __future__ import annotations

import argparse
import json
import re
import socket
import sys
import threading
import time
from pathlib import Path
from typing import Any

import numpy as np
import zstandard

from gaitshift.control.locomotion_driver import LocomotionDriver
from gaitshift.robots import load_robot
from gaitshift.scenario import load_scenario
from gaitshift.sim.scenario_run import simulate_scenario
from gaitshift.sim.teleop import Session
from gaitshift.sim.web import CommandRange, WebView

PRESSES = 5  # vx slider key presses (+0.05 m/s each)
#: page script: when (epoch ms) each status time "t = X s" appears in the page's DOM
RECORDER = """
window.__shown = [];
new MutationObserver((muts) => {
  const ts = performance.timeOrigin + performance.now();
  for (const m of muts) {
    const nodes = m.type === "characterData" ? [m.target] : m.addedNodes;
    for (const n of nodes) {
      const r = (n.textContent || "").match(/t = (\\d+\\.\\d\\d) s/);
      if (r) { window.__shown.push([ts, r[1]]); return; }
    }
  }
}).observe(document, { subtree: true, childList: true, characterData: true });
"""
STATUS = re.compile(rb"t = (\d+\.\d\d) s")
ZSTD = b"\x28\xb5\x2f\xfd"  # zstd frame magic


def _port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _session(script: list[tuple[str, float]] | None) -> tuple[LocomotionDriver, Session, Any]:
    cfg = load_robot("g1")
    sc = load_scenario({"planner": "locomotion", "name": "bench-web", "robot": "g1"})
    drv = LocomotionDriver.live(sc, cfg.facts(), 0.002, 120.0)
    return drv, Session(drv, script=script, status=lambda _: None), cfg


class TimedView(WebView):
    """A view that records the send time of each status frame and of each applied command."""

    def __init__(self, *args: Any, **kw: Any) -> None:
        super().__init__(*args, **kw)
        self.sent: dict[str, float] = {}
        self.first_tick = 0.0

    def __call__(self, k: int, t: float, d: Any) -> None:
        if not self.first_tick:
            self.first_tick = time.time()
        super().__call__(k, t, d)

    def draw(self, t: float, d: Any) -> None:
        super().draw(t, d)
        self.sent.setdefault(f"{t:.2f}", time.time())


def run_no_view() -> dict[str, float]:
    """A run without a view (walk at 0.2 m/s for 6 s, stop): process CPU s per simulated s, real-time factor."""
    drv, session, cfg = _session([("up", 0.0), ("up", 0.0), ("wait", 6.0), ("quit", 0.0)])
    c0 = time.process_time()
    r = simulate_scenario(drv.sc, cfg, driver=drv, hooks=[session], control_period=0.002).result
    return {"cpu_per_s": (time.process_time() - c0) / r.meta["sim_time_s"], "rtf": float(r.meta["real_time_factor"])}


def run_view(backend: str, pw: Any, cpu_per_s: float, shot: Path | None) -> dict[str, Any]:
    """One watched, commanded run with ``backend`` (module docstring)."""
    drv, session, cfg = _session(None)
    applied: list[float] = []

    def on_command(vx: float, vy: float, yaw: float, t: float) -> None:
        applied.append(time.time())
        session.set_command(vx, vy, yaw, t)

    lim = drv.gen.p.limits
    t0 = time.perf_counter()
    view = TimedView(
        lambda: drv.trajectory,
        port=_port(),
        backend=backend,
        controls=CommandRange(*lim.max_speed, lim.max_yaw_rate),
        on_command=on_command,
        on_quit=session.quit,
    )
    server_start = time.perf_counter() - t0
    browser = pw.chromium.launch(executable_path="/usr/bin/chromium", headless=True, args=["--no-sandbox"])
    page = browser.new_page(viewport={"width": 1280, "height": 800})
    page.add_init_script(RECORDER)
    frames: list[tuple[int, bytes | None]] = []  # (bytes, status time) of each websocket message, in order

    def on_frame(payload: Any) -> None:
        data = payload if isinstance(payload, bytes) else payload.encode()
        z = data.find(ZSTD)  # viser's wire messages: a header, then a zstd frame of msgpack
        inner = zstandard.ZstdDecompressor().decompressobj().decompress(data[z:]) if z >= 0 else data
        m = STATUS.search(inner)
        frames.append((len(data), m.group(1) if m else None))

    page.on("websocket", lambda ws: ws.on("framereceived", on_frame))
    page.goto(view.url)
    page.get_by_text("waiting for the simulation").wait_for(timeout=60_000)
    result: dict[str, Any] = {}
    c0 = time.process_time()
    opts = {"control_period": 0.002}
    sim = threading.Thread(
        target=lambda: result.update(r=simulate_scenario(drv.sc, cfg, driver=drv, hooks=[session, view], **opts).result)
    )
    sim.start()
    page.get_by_text("commanded: vx = +0.00").wait_for(timeout=180_000)
    slider = page.get_by_role("slider").first
    presses = []
    for i in range(PRESSES):
        page.wait_for_timeout(700)
        presses.append(time.time())
        slider.press("ArrowRight")
        end = time.time() + 30
        while len(applied) <= i and time.time() < end:
            page.wait_for_timeout(10)
    page.wait_for_timeout(3000)
    if shot is not None:  # walking at 0.25 m/s
        page.screenshot(path=str(shot))
    page.get_by_role("button", name="End run").click()
    while sim.is_alive():
        page.wait_for_timeout(200)
    sim.join()
    shown = [(ts / 1e3, t) for ts, t in page.evaluate("window.__shown")]
    cpu = time.process_time() - c0
    browser.close()
    view.close()
    first = next(i for i, f in enumerate(frames) if f[1] == b"0.00")
    lat = [ts - view.sent[t] for ts, t in shown if t in view.sent]
    first_shown = shown[0][0]  # the page may skip statuses while it loads the scene
    cmd_lat = [a - p for p, a in zip(presses, applied, strict=False)] or [float("nan")]
    n = len(view.update_wall)
    sim_s = float(result["r"].meta["sim_time_s"])
    wall = np.asarray(view.update_wall) * 1e3
    run_wall = (view.sent[max(view.sent, key=float)] - view.first_tick) or float("nan")
    return {
        "backend": backend,
        "server_start_s": round(server_start, 3),
        "first_frame_s": round(first_shown - view.first_tick, 3),
        "first_status_t": float(shown[0][1]),
        "scene_bytes": int(sum(f[0] for f in frames[: first + 1])),
        "bytes_per_frame": int(sum(f[0] for f in frames[first + 1 :]) / max(n - 1, 1)),
        "frames": n,
        "update_wall_ms": [round(float(np.median(wall[1:])), 2), round(float(np.percentile(wall[1:], 95)), 2)],
        "cpu_ms_per_frame": round((cpu - cpu_per_s * sim_s) / n * 1e3, 2),
        "sim_s": round(sim_s, 2),
        "frames_per_s": round(n / run_wall, 1),
        "view_latency_ms": [round(float(np.median(lat)) * 1e3, 1), round(float(np.percentile(lat, 95)) * 1e3, 1)],
        "command_latency_ms": [
            round(float(np.median(cmd_lat)) * 1e3, 1),
            round(float(np.percentile(cmd_lat, 95)) * 1e3, 1),
        ],
        "commands_applied": len(applied),
        "rtf": round(float(result["r"].meta["real_time_factor"]), 3),
    }


def run_micro(backend: str, n: int = 300) -> dict[str, Any]:
    """Scene update alone, no browser, no simulation: the G1 posed at ``n`` random joint angles; CPU
    ms per update (the calling thread, and the whole process: viser's threads included)."""
    import mujoco
    import viser

    from gaitshift.sim.plant import build_plant
    from gaitshift.sim.web_scene import build_scene

    m = build_plant(0.002, "g1").model
    d = mujoco.MjData(m)
    rng = np.random.default_rng(0)
    server = viser.ViserServer(host="127.0.0.1", port=_port(), verbose=False)
    t0 = time.perf_counter()
    scene = build_scene(backend, server, m)
    build = time.perf_counter() - t0
    poses = []
    for _ in range(n):
        d.qpos[:3], d.qpos[7:] = rng.normal(0, 0.1, 3) + np.array([0, 0, 0.75]), rng.normal(0, 0.2, m.nq - 7)
        mujoco.mj_kinematics(m, d)
        poses.append((d.xpos.copy(), d.xquat.copy(), d.xmat.copy()))
    c0, th0 = time.process_time(), time.thread_time()
    for xpos, xquat, xmat in poses:
        d.xpos[:], d.xquat[:], d.xmat[:] = xpos, xquat, xmat
        scene.update(d)
    cpu, th = time.process_time() - c0, time.thread_time() - th0
    server.stop()
    return {
        "backend": backend,
        "scene_build_s": round(build, 3),
        "update_thread_cpu_ms": round(th / n * 1e3, 3),
        "update_process_cpu_ms": round(cpu / n * 1e3, 3),
    }


def main() -> None:
    """Both builders, each after a run without a view (the CPU baseline); print and write the JSON."""
    ap = argparse.ArgumentParser()
    ap.add_argument("--screenshot", type=Path, default=None, help="PNG of the page of the default builder (viser)")
    ap.add_argument("--backends", default="mjviser,viser", help="builders to measure, comma-separated")
    ap.add_argument("--out", type=Path, default=Path(__file__).with_name("web_view.json"))
    args = ap.parse_args()
    from playwright.sync_api import sync_playwright

    backends = args.backends.split(",")
    micro = [run_micro(b) for b in backends]
    print(json.dumps(micro), file=sys.stderr)
    rows: list[dict[str, Any]] = []
    with sync_playwright() as pw:
        for backend in backends:
            base = run_no_view()
            row = run_view(backend, pw, base["cpu_per_s"], args.screenshot if backend == "viser" else None)
            row["rtf_no_view"] = round(base["rtf"], 3)
            rows.append(row)
            print(json.dumps(row), file=sys.stderr)
    with open("/proc/loadavg") as f:
        load = f.read().split()[:3]
    out = {"machine": {"cores": 2, "loadavg_1_5_15": load}, "micro": micro, "runs": rows}
    args.out.write_text(json.dumps(out, indent=1) + "\n")
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
