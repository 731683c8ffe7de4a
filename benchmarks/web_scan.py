"""Measure what drawing the depth scan costs the tick of ``simulate --web``.

The perceived run of ``docs/perception/g1-stairs-up-ahead.yaml`` (seed 0, 10.6 simulated s, 5300
ticks, 312 depth frames of up to 768 points) with the browser view as its tick hook, not paced
(``realtime=False``: the hook's own cost, not sleeping), the view drawing the scan (``draw_scan``
True) or not (False, the map and everything else still drawn), the runs alternating. With
``--browser`` a headless Chromium (``/usr/bin/chromium``, playwright) has the page open during the
run, so every message is also sent. Per run:

- ``hook_ms_per_tick``: the view hook's wall time per tick (dispatch + the frames it draws), mean;
- ``hook_p99_ms``: its 99th percentile over the ticks (the ticks that draw a frame);
- ``frame_ms``: one frame's update, median and p95 (``WebView.update_wall``);
- ``scan_ms``: one scan's drawing alone (``WebView._draw_scan`` timed), median (draw_scan only);
- ``run_wall_s``: the whole run.

Usage: ``PYTHONPATH=src .venv/bin/python benchmarks/web_scan.py [--repeats 2] [--browser]``; prints
one JSON object (also written to ``benchmarks/web_scan.json``).
"""

from __future__ import annotations

import argparse
import json
import socket
import time
from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.control.drivers import prepare
from gaitshift.sim.scenario_run import run_prepared
from gaitshift.sim.web import WebView

ROOT = Path(__file__).resolve().parents[1]
SCENARIO = ROOT / "docs" / "perception" / "g1-stairs-up-ahead.yaml"


def _port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


class Timed:
    """The view as a tick hook, each call timed (wall s)."""

    def __init__(self, view: WebView) -> None:
        self.view, self.wall = view, list[float]()
        self.scan = list[float]()
        draw = view._draw_scan

        def timed_scan() -> None:
            w0 = time.perf_counter()
            n = view._scan_frames
            draw()
            if view._scan_frames != n:
                self.scan.append(time.perf_counter() - w0)

        view._draw_scan = timed_scan  # type: ignore[method-assign]

    def attach(self, ctrl: Any) -> None:
        self.view.attach(ctrl)

    def __call__(self, k: int, t: float, d: Any) -> None:
        w0 = time.perf_counter()
        self.view(k, t, d)
        self.wall.append(time.perf_counter() - w0)


def run(draw_scan: bool, pw: Any) -> dict[str, Any]:
    """One perceived run with the view (as ``simulate --web`` makes it, not paced), the scan drawn or not."""
    prepared = prepare(str(SCENARIO), None, 0.002, None)
    _, _, driver, traj = prepared
    view = WebView(lambda: driver.trajectory if driver else traj, port=_port())
    view.draw_scan = draw_scan
    hook = Timed(view)
    browser = None
    if pw is not None:
        browser = pw.chromium.launch(executable_path="/usr/bin/chromium", headless=True, args=["--no-sandbox"])
        browser.new_page(viewport={"width": 1280, "height": 800}).goto(view.url)
        time.sleep(3.0)  # the page connected
    w0 = time.perf_counter()
    result = run_prepared(prepared, hooks=[hook], seed=0).result
    wall = time.perf_counter() - w0
    view.close()
    if browser is not None:
        browser.close()
    ticks = np.array(hook.wall) * 1e3
    frames = np.array(view.update_wall) * 1e3
    return {
        "draw_scan": draw_scan,
        "ticks": len(ticks),
        "frames": len(frames),
        "scans_drawn": len(hook.scan),
        "hook_ms_per_tick": float(ticks.mean()),
        "hook_p99_ms": float(np.percentile(ticks, 99)),
        "frame_ms": [float(np.median(frames)), float(np.percentile(frames, 95))],
        "scan_ms": float(np.median(hook.scan) * 1e3) if hook.scan else None,
        "run_wall_s": wall,
        "fell": bool(result.fell),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--browser", action="store_true", help="a headless Chromium has the page open")
    ap.add_argument("--json", type=Path, default=ROOT / "benchmarks" / "web_scan.json")
    args = ap.parse_args()
    runs: list[dict[str, Any]] = []
    pw_ctx = None
    pw = None
    if args.browser:
        from playwright.sync_api import sync_playwright

        pw_ctx = sync_playwright()
        pw = pw_ctx.start()
    try:
        for _ in range(args.repeats):
            for draw_scan in (True, False):
                runs.append(run(draw_scan, pw))
                print(json.dumps(runs[-1]), flush=True)
    finally:
        if pw_ctx is not None and pw is not None:
            pw.stop()
    load = Path("/proc/loadavg").read_text().split()[:3] if Path("/proc/loadavg").exists() else []
    out = {"scenario": SCENARIO.name, "browser": args.browser, "loadavg_end": load, "runs": runs}
    args.json.write_text(json.dumps(out, indent=1) + "\n")
    print(json.dumps(out))


if __name__ == "__main__":
    main()
