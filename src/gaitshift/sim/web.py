"""Live view of a closed-loop run in the browser (viser): the robot, footsteps, CoM, ZMP, and, in a
live session, the speed command.

:class:`WebView` is a tick hook of :func:`gaitshift.sim.loop.simulate` (called with the tick, plan
time s and the plant's ``MjData``). It starts a viser server at construction (the page answers
before the run starts); the scene is built at the first tick from ``d.model``
(:mod:`gaitshift.sim.web_scene`). It draws at most ``rate`` frames per second of simulated time
(default 30 Hz, not every 2 ms tick):

- the robot's bodies, posed from ``xpos`` / ``xquat``;
- the planned footholds (``footsteps`` (K, 4): x, y, z m, yaw rad) as sole outlines, left blue,
  right red;
- the CoM ``subtree_com[0]`` (orange sphere, and its trail of the last :data:`TRAIL` frames);
- the measured ZMP: on flat ground the centre of pressure of the floor contacts,
  ``p = sum_i f_z,i c_i / sum_i f_z,i`` (green disc; hidden in flight), and the planned ZMP of the
  sample being tracked (small dark green sphere);
- the controller's elevation map (a robot with a depth camera, :mod:`gaitshift.control.perception`):
  its seen cells at their heights, coloured by height, and its edge cells (a step of more than
  :data:`~gaitshift.control.perception.EDGE_STEP` to a neighbour) as larger red points, redrawn every
  :data:`MAP_EVERY` frames;
- the latest depth scan the controller fused (:attr:`Perceiver.scan
  <gaitshift.control.perception.perceiver.Perceiver.scan>`: the frame's points placed with the
  ESTIMATED camera pose, the brain's view, not the world's truth), magenta, redrawn at each frame that
  has a new scan (the camera's 30 Hz against the view's 30 Hz: about every frame), at most
  :data:`~gaitshift.control.perception.SCAN_POINTS` points (thinned evenly; the G1's camera gives at
  most 32 x 24 = 768);
- a status panel: plan time, gait, measured CoM speed in the heading frame (m/s), the command the
  plan carries at that sample (vx, vy m/s, yaw rate rad/s), the real-time factor (simulated s per
  wall-clock s since the first tick) and the page updates per second.

With ``controls`` (a live session) the panel has sliders for vx, vy and the yaw rate and the buttons
*Stop* (command zero: the robot slows to zero speed and keeps stepping in place) and *End run*
(stop at rest and end the session).
The page's callbacks run in viser's threads: they only queue the command, and the hook applies it
in the simulation thread through ``on_command(vx, vy, yaw_rate, t)`` / ``on_quit(t)``. A caller outside
the simulation loop (the brain's page, :mod:`gaitshift.dds.brain_web`) calls the hook's two halves itself:
:meth:`WebView.dispatch` (the queued commands) and :meth:`WebView.show` (a frame when one is due).
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np

from gaitshift.sim.web_scene import RobotScene, build_scene

__all__ = ["SLIDER_STEP", "TRAIL", "CommandRange", "WebView", "floor_cop"]

#: CoM trail length, frames
TRAIL = 90
GAITS = ("stand", "walk", "run")
#: slider step of the command sliders (m/s, rad/s)
SLIDER_STEP = 0.05
#: the map is redrawn every this many frames
MAP_EVERY = 15
#: sole outline drawn at each foothold (length, width), m
SOLE = (0.20, 0.09)


@dataclass(frozen=True)
class CommandRange:
    """Slider ranges of a live session: largest forward and backward vx, |vy| (m/s), |yaw rate| (rad/s)."""

    forward: float
    backward: float
    lateral: float
    yaw_rate: float


def floor_cop(d: mujoco.MjData, floor_geom: int) -> np.ndarray | None:
    """Centre of pressure of the contacts with the floor geom, (3,) m, or None without load.

    ``p = sum_i f_n,i c_i / sum_i f_n,i`` over the contacts i touching ``floor_geom`` (``c_i`` the
    contact position, ``f_n,i`` its normal force from ``mj_contactForce``, N); on flat ground this is
    the ZMP of the robot."""
    m = d.model
    f6 = np.zeros(6)
    total, acc = 0.0, np.zeros(3)
    for ci in range(d.ncon):
        con = d.contact[ci]
        if floor_geom not in (con.geom[0], con.geom[1]):
            continue
        mujoco.mj_contactForce(m, d, ci, f6)
        total += f6[0]
        acc += f6[0] * con.pos
    return acc / total if total > 1e-6 else None


def _sole_outlines(steps: np.ndarray, side: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Line segments (4K, 2, 3) of the sole rectangles at footholds ``steps`` (K, 4) and their colours."""
    a, b = SOLE[0] / 2, SOLE[1] / 2
    corners = np.array([[a, b], [-a, b], [-a, -b], [a, -b]])
    segs = []
    for x, y, z, yaw in steps:
        c, s = math.cos(yaw), math.sin(yaw)
        pts = corners @ np.array([[c, s], [-s, c]]) + [x, y]
        p3 = np.column_stack([pts, np.full(4, z + 0.003)])
        segs.extend([[p3[j], p3[(j + 1) % 4]] for j in range(4)])
    colours = np.where(np.repeat(side, 4)[:, None, None] == 0, [[30, 90, 220]], [[220, 50, 40]])
    return np.asarray(segs).reshape(-1, 2, 3), np.broadcast_to(colours, (4 * len(steps), 2, 3)).copy()


class WebView:
    """The browser view hook (module docstring).

    Args:
        plan: returns the trajectory being tracked now (a live driver's plan grows).
        port, host: where the page is served (``http://host:port``).
        backend: scene builder of :data:`gaitshift.sim.web_scene.SCENES`.
        rate: frames per second of simulated time (<= 30 recommended).
        controls: slider ranges for a live session, or None (a view only).
        on_command, on_quit: apply a queued command / end request in the simulation thread.
        realtime: pace the run to the wall clock (a session pacing itself passes False).
    """

    def __init__(
        self,
        plan: Callable[[], Any],
        port: int = 8080,
        host: str = "127.0.0.1",
        backend: str = "viser",
        rate: float = 30.0,
        controls: CommandRange | None = None,
        on_command: Callable[[float, float, float, float], None] | None = None,
        on_quit: Callable[[float], None] | None = None,
        realtime: bool = False,
    ) -> None:
        import viser

        self.plan, self.backend, self.period, self.realtime = plan, backend, 1.0 / rate, realtime
        self.on_command, self.on_quit, self.floor, self.nodes = on_command, on_quit, 0, dict[str, Any]()
        self.server = viser.ViserServer(host=host, port=port, verbose=False)
        self.url = f"http://{host}:{self.server.get_port()}"
        cam = self.server.initial_camera  # the scene follows the pelvis, which stays at the origin
        cam.position, cam.look_at = (1.6, -2.4, 0.5), (0.0, 0.0, -0.3)
        self.scene: RobotScene | None = None
        self._lock = threading.Lock()
        self._pending: list[tuple[str, tuple[float, float, float]]] = []
        self._next, self._wall0, self._frames, self._trail = 0.0, 0.0, 0, np.zeros((0, 3))
        self._steps_key: int | None = None  # a hash of the footholds drawn
        self.update_wall: list[float] = []  # wall-clock s of each frame update (measurements)
        self.elevation: Any = None  # the controller's elevation map (attach), drawn every MAP_EVERY frames
        self.perceiver: Any = None  # the controller's perceiver (attach): its last scan, drawn when new
        self._scan_frames = 0  # the perceiver's frame count at the scan drawn
        self.draw_scan = True  # False: the scan is not drawn (the map still is; a measurement's baseline)
        self.status = self.server.gui.add_markdown("waiting for the simulation ...")
        self.note = ""  # a first line of the panel (the brain's phase), Markdown
        self.sliders: dict[str, Any] = {}
        if controls is not None:
            self._add_controls(controls)

    def _add_controls(self, r: CommandRange) -> None:
        gui = self.server.gui
        step = SLIDER_STEP

        def down(x: float) -> float:  # the range in whole steps (the generator clamps at the limit)
            return round(math.floor(x / step + 1e-9) * step, 6)

        with gui.add_folder("Command"):
            self.sliders = {
                "vx": gui.add_slider("vx (m/s)", -down(r.backward), down(r.forward), step, 0.0),
                "vy": gui.add_slider("vy (m/s)", -down(r.lateral), down(r.lateral), step, 0.0),
                "yaw": gui.add_slider("yaw rate (rad/s)", -down(r.yaw_rate), down(r.yaw_rate), step, 0.0),
            }
            stop, end = gui.add_button("Stop"), gui.add_button("End run")
        for s in self.sliders.values():
            s.on_update(lambda _: self._queue("command", self._slider_command()))
        stop.on_click(lambda _: self._stop())
        end.on_click(lambda _: self._queue("quit", (0.0, 0.0, 0.0)))

    def attach(self, ctrl: Any) -> None:
        """The run's controller (:data:`gaitshift.sim.loop.TickHook`): when its robot has a depth camera,
        its elevation map is drawn (cells coloured by height, edges red) and its last scan (magenta)."""
        self.perceiver = getattr(ctrl, "perceiver", None)
        self.elevation = self.perceiver.map if self.perceiver is not None else None

    def _draw_map(self) -> None:
        """The map's seen cells at their heights (coloured by height) and its edge cells (red, larger)."""
        from matplotlib import colormaps

        from gaitshift.control.perception import EDGE_COLOR, seen_cells

        assert self.scene is not None
        m, sc = self.elevation, self.server.scene
        if not m.known.any():
            return
        r = m.settings.resolution
        points, shade, edge = seen_cells(m.height, m.known, m.corner * r, r)
        rgb = (255 * colormaps["viridis"](shade)[:, :3]).astype(np.uint8)
        xyz = points.astype(np.float32)
        root = self.scene.root
        self.nodes["map"] = sc.add_point_cloud(f"{root}/elevation_map", xyz, rgb, point_size=0.03, precision="float32")
        if edge.any() or "map_edges" in self.nodes:
            self.nodes["map_edges"] = sc.add_point_cloud(
                f"{root}/map_edges", xyz[edge], EDGE_COLOR, point_size=0.045, precision="float32"
            )

    def _draw_scan(self) -> None:
        """The perceiver's last scan (world frame as the controller estimates it), when it has a new one."""
        p = self.perceiver
        if p.frames == self._scan_frames or not len(p.scan):
            return
        self._scan_frames = p.frames
        from gaitshift.control.perception import SCAN_COLOR, thin_scan

        pts = thin_scan(p.scan)
        if "scan" in self.nodes:
            self.nodes["scan"].points = pts
        else:
            assert self.scene is not None
            self.nodes["scan"] = self.server.scene.add_point_cloud(
                f"{self.scene.root}/scan", pts, SCAN_COLOR, point_size=0.015, precision="float32"
            )

    def _slider_command(self) -> tuple[float, float, float]:
        return (float(self.sliders["vx"].value), float(self.sliders["vy"].value), float(self.sliders["yaw"].value))

    def _stop(self) -> None:
        for s in self.sliders.values():
            s.value = 0.0  # the page follows; a callback this may fire queues the same zero command
        self._queue("command", (0.0, 0.0, 0.0))

    def _queue(self, kind: str, cmd: tuple[float, float, float]) -> None:
        with self._lock:
            self._pending.append((kind, cmd))

    def __call__(self, _k: int, t: float, d: mujoco.MjData) -> None:
        """The tick hook: apply queued page commands; draw when a frame is due; pace if asked."""
        self.dispatch(t)
        self.show(t, d)
        if self.realtime:
            lag = t - (time.perf_counter() - self._wall0)
            if lag > 0:
                time.sleep(lag)

    def dispatch(self, t: float) -> None:
        """Hand the page's queued commands to ``on_command`` / ``on_quit`` (at ``t`` s), in the caller's thread."""
        with self._lock:
            pending, self._pending = self._pending, []
        for kind, cmd in pending:
            if kind == "command" and self.on_command is not None:
                self.on_command(*cmd, t)
            elif kind == "quit" and self.on_quit is not None:
                self.on_quit(t)

    def show(self, t: float, d: mujoco.MjData) -> None:
        """Draw the robot posed in ``d`` at plan time ``t`` s when a frame is due (the scene built first)."""
        if self.scene is None:
            self.build(d.model)
        if t + 1e-9 >= self._next:
            self._next += self.period
            w0 = time.perf_counter()
            self.draw(t, d)
            self.update_wall.append(time.perf_counter() - w0)

    def build(self, m: mujoco.MjModel) -> None:
        """The scene of model ``m``: the robot and the overlay nodes (moved by :meth:`draw`); at the first
        frame unless called before (a run whose first frames must not wait for it)."""
        self.scene = build_scene(self.backend, self.server, m)
        planes = [g for g in range(m.ngeom) if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_PLANE and m.geom_bodyid[g] == 0]
        self.floor = planes[0] if planes else 0
        sc, root = self.server.scene, self.scene.root
        self.nodes = {
            "com": sc.add_icosphere(f"{root}/com", radius=0.04, color=(255, 140, 0)),
            "zmp": sc.add_cylinder(f"{root}/zmp", radius=0.035, height=0.006, color=(20, 170, 60)),
            "zmp_plan": sc.add_icosphere(f"{root}/zmp_plan", radius=0.015, color=(0, 90, 30)),
            "trail": sc.add_point_cloud(
                f"{root}/com_trail", np.zeros((1, 3)), (255, 140, 0), point_size=0.012, precision="float32"
            ),
        }
        self._wall0 = time.perf_counter()

    def draw(self, t: float, d: mujoco.MjData) -> None:
        """One frame: robot, overlays, and (every 6th frame) the status panel."""
        assert self.scene is not None
        traj, nodes = self.plan(), self.nodes
        i = min(round(t / traj.dt), len(traj) - 1)
        with self.server.atomic():
            self.scene.update(d)
            key = hash(np.round(traj.footsteps, 3).tobytes())  # any foothold added or moved (perceived terrain)
            if key != self._steps_key:  # a foothold was planned or moved
                self._steps_key = key
                segs, cols = _sole_outlines(traj.footsteps, traj.footstep_side)
                self.server.scene.add_line_segments(f"{self.scene.root}/footsteps", segs, cols, thickness=0.012)
            com = d.subtree_com[0].copy()
            self._trail = np.vstack([self._trail, com])[-TRAIL:]
            nodes["com"].position = com
            nodes["trail"].points = self._trail.astype(np.float32)
            cop = floor_cop(d, self.floor)
            nodes["zmp"].visible = cop is not None
            if cop is not None:
                nodes["zmp"].position = cop
            zp = traj.zmp[i]
            nodes["zmp_plan"].visible = bool(np.all(np.isfinite(zp)))
            if nodes["zmp_plan"].visible:
                nodes["zmp_plan"].position = zp
            self._frames += 1
            if self.elevation is not None and self._frames % MAP_EVERY == 1:
                self._draw_map()
            if self.perceiver is not None and self.draw_scan:
                self._draw_scan()
            if self._frames % 6 == 1:
                self.status.content = self.status_text(t, d, traj, i)
        self.server.flush()

    def status_text(self, t: float, d: mujoco.MjData, traj: Any, i: int) -> str:
        """The panel text: time, gait, speed, command, real-time factor, page update rate."""
        psi = float(traj.heading[i])
        v = d.subtree_linvel[0]
        vh = (math.cos(psi) * v[0] + math.sin(psi) * v[1], -math.sin(psi) * v[0] + math.cos(psi) * v[1])
        wall = time.perf_counter() - self._wall0
        cmd, yaw = traj.command_vel[i], float(traj.command_yaw_rate[i])
        commanded = (
            f"commanded: vx = {cmd[0]:+.2f} m/s, vy = {cmd[1]:+.2f} m/s, yaw rate = {yaw:+.2f} rad/s"
            if np.all(np.isfinite(cmd)) and math.isfinite(yaw)
            else "commanded: none (a plan over given footsteps)"
        )
        return self.note + (
            f"**t = {t:.2f} s** · gait **{GAITS[int(traj.gait[i])]}**\n\n"
            f"speed: vx = {vh[0]:+.2f} m/s, vy = {vh[1]:+.2f} m/s\n\n"
            f"{commanded}\n\n"
            f"real-time factor = {t / wall if wall > 0 else 0.0:.2f} · {self._frames / max(wall, 1e-9):.0f} "
            "frames/s"
        )

    def close(self) -> None:
        """Stop the server (the page goes away)."""
        self.server.stop()
