"""Speed of perception (docs/perception.md, "Cost"), baselines measured in the same run.

The G1 stands 0.5 m before g1-stairs-up's three 10 cm stairs, its head camera (the robot YAML's
D435i: 32 x 24 rays, 30 Hz) looking at them.

* ``G1 depth frame (DepthCameraSim.read)``: one frame of the simulated camera (the world's side:
  ``mj_multiRay`` over every pixel, noise, dropout); the baseline casts the same rays one ``mj_ray`` at
  a time in Python.
* ``G1 map update (Perceiver.frame)``: the controller's side: the frame placed with the camera pose
  (eq. (1) of :mod:`gaitshift.control.perception.perceiver`) and fused into the map (eq. (1) of
  :mod:`gaitshift.control.perception.elevation_map`); the baseline fuses the same points one at a
  time in Python (the per-point Kalman update).

* ``G1 perceived re-plan (PerceivedDriver at a boundary)``: the controller's foothold search at a phase
  boundary of g1-stairs-up with its stairs 1 m ahead (docs/perception/g1-stairs-up-ahead.yaml), on a
  map that has seen them: the believed terrain read off the map, the footholds placed on it, the rest
  of the plan re-solved and sampled (:mod:`gaitshift.control.perceived_driver`); the baseline plans the
  whole scenario from scratch on the true terrain (``gaitshift.plan``).

* ``G1 map hand-over (ElevationMap.snapshot + file)``: what the tick pays at a re-plan's instant when a
  worker process re-plans (:mod:`gaitshift.control.replanner`, "A driver that reads the map"): the map
  copied and written to a file of the worker's folder (in /dev/shm); the baseline is that instant's
  re-plan made in the tick (``replan: inline``), as above.

The note gives the map update's share of a 2 ms tick, averaged over the ticks between frames.
"""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from gaitshift.bench import Result, benchmark, timed

#: the stairs the camera looks at (g1-stairs-up's treads, shifted 0.25 m further: the robot stands at 0)
STAIRS = ((0.5, 0.75, 0.1), (0.75, 1.0, 0.2), (1.0, 3.0, 0.3))


def _scene() -> tuple[Any, Any, Any, Any]:
    """The plant, its data with the G1 standing, its camera and the camera's simulator."""
    from gaitshift.models.terrain import Piece, Terrain
    from gaitshift.sim.depth_camera import DepthCameraSim
    from gaitshift.sim.plant import build_plant

    terrain = Terrain(tuple(Piece(x0, x1, z, z) for x0, x1, z in STAIRS))
    plant = build_plant(0.002, "g1", terrain)
    m = plant.model
    d = mujoco.MjData(m)
    d.qpos[:] = plant.robot.standing_qpos(m)
    d.qpos[2] = 0.76
    mujoco.mj_forward(m, d)
    cam = plant.robot.sensors.depth_camera
    assert cam is not None  # the G1 YAML's D435i
    return m, d, cam, DepthCameraSim(m, cam, 0.002, seed=0)


def _ray_by_ray(m: Any, d: Any, sim: Any) -> None:
    """The baseline camera: the same rays, one ``mj_ray`` each."""
    rot = d.site_xmat[sim.site].reshape(3, 3)
    geom = np.zeros(1, np.int32)
    for ray in sim.rays @ rot.T:
        mujoco.mj_ray(m, d, d.site_xpos[sim.site], ray, sim.groups, 1, -1, geom)


def _point_by_point(per: Any, world: np.ndarray, var: np.ndarray) -> None:
    """The baseline fusion: eq. (1) of the map one point at a time."""
    m = per.map
    for p, v in zip(world, var, strict=True):
        i, j = m.cells(p[None, :2])[0] - m.corner
        if 0 <= i < m.n and 0 <= j < m.n:
            prior = 1.0 / m.variance[i, j]
            post = 1.0 / (prior + 1.0 / v)
            m.height[i, j] = post * (prior * m.height[i, j] + p[2] / v)
            m.variance[i, j] = post


@benchmark("perception")
def bench_perception(quick: bool) -> list[Result]:
    from gaitshift.control.perception import Perceiver

    m, d, cam, sim = _scene()
    reps = 20 if quick else 500
    frame = timed(
        "G1 depth frame (DepthCameraSim.read)",
        f"{len(sim.rays)} rays, stairs ahead",
        lambda: sim.read(d, 0),
        reps,
        baseline=("one mj_ray per pixel in Python", lambda: _ray_by_ray(m, d, sim), max(5, reps // 10)),
    )
    pts = sim.read(d, 0)
    assert pts is not None
    per = Perceiver(m, cam)
    rot, o = d.site_xmat[per.site].reshape(3, 3), d.site_xpos[per.site]
    world = o + pts @ rot.T
    var = np.full(len(pts), 1e-4)
    update = timed(
        "G1 map update (Perceiver.frame)",
        f"{len(pts)} points into a {per.map.n} x {per.map.n} map",
        lambda: per.frame(0.0, pts, d),
        reps,
        baseline=(
            "point-by-point Kalman update in Python",
            lambda: _point_by_point(per, world, var),
            max(5, reps // 10),
        ),
    )
    share = (frame.median_s + update.median_s) / sim.every / 0.002 * 100
    note = f"camera + map every {sim.every} ticks: {share:.2f} % of a 2 ms tick on average"
    replan, handover = _replan(max(3, reps // 25), reps)
    return [frame, Result(**{**update.__dict__, "note": note}), replan, handover]


def _replan(reps: int, handover_reps: int) -> tuple[Result, Result]:
    """The perceived driver's re-plan at boundary 3, and the whole plan from scratch; the map's hand-over to
    a worker process, and the same re-plan in the tick (module docstring)."""
    import yaml

    import gaitshift
    from gaitshift.control.drivers import prepare
    from gaitshift.control.perceived_driver import PerceivedDriver
    from gaitshift.control.perception import ElevationMap
    from gaitshift.control.planner_worker import map_folder
    from gaitshift.scenario.loader import builtin_text
    from gaitshift.scenario.terrain import terrain_of

    sc = yaml.safe_load(builtin_text("g1-stairs-up"))
    sc["gait"] = [{"gait": "walk", "steps": 10}]
    sc["terrain"] = [{"x": [x0 + 0.5, x1 + 0.5], "z": [z, z]} for x0, x1, z in STAIRS]
    world, _, driver, _ = prepare(sc, None, 0.002, "perceived")
    assert isinstance(driver, PerceivedDriver)
    emap = ElevationMap()
    emap.recenter(np.array([1.0, 0.0]))
    xy = emap.centres().reshape(-1, 2)
    emap.fuse(np.column_stack([xy, terrain_of(world.terrain).height(xy[:, 0])]), np.full(len(xy), 1e-6))
    driver.see(emap)
    start = (driver.seq, driver.bp, driver.trajectory, driver.belief)
    t3 = float(driver.seq.boundary_times[3])

    def once() -> None:
        driver.seq, driver.bp, driver.trajectory, driver.belief = start
        driver.next = 3
        assert driver.maybe_replan(t3, np.zeros(3), np.zeros(3)) is not None

    replan = timed(
        "G1 perceived re-plan (PerceivedDriver at a boundary)",
        f"{len(driver.seq.footsteps)} footholds, {len(start[2])} samples",
        once,
        reps,
        baseline=("the whole plan from scratch (gaitshift.plan)", lambda: gaitshift.plan(world), reps),
    )
    with tempfile.TemporaryDirectory(dir="/dev/shm" if Path("/dev/shm").is_dir() else None) as tmp:
        folder, n = map_folder(Path(tmp)), iter(range(1, 10**9))
        handover = timed(
            "G1 map hand-over (ElevationMap.snapshot + file)",
            f"{emap.n} x {emap.n} cells to a worker process",
            lambda: folder.write(next(n), emap.snapshot()),
            handover_reps,
            baseline=("the re-plan in the tick (replan: inline)", once, reps),
        )
    return replan, handover
