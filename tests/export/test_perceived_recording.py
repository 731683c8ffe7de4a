"""The Rerun recording of a perceived run (docs/perception/g1-stairs-up-ahead.yaml, seed 0: the G1 walks
up three 10 cm stairs it only sees), read back with the Rerun SDK and judged against the world's terrain:

* ``world/scan`` holds one point cloud per depth frame the controller fused, at the camera's rate, and
  its points lie on the true terrain surface (treads and risers) within the camera's stated range noise
  (3 sigma(r), sigma(r) = sigma_0 + k r^2) plus the error of the camera pose the controller placed them
  with (the estimate's, measured here by forward kinematics of the logged true and estimated states);
* ``world/footsteps`` holds every re-plan's footholds at the time of the re-plan: the first set (the
  blind plan) stands at z = 0 over the stairs, later sets move onto the treads, and the last set stands
  on the true treads (within 1 cm plus the estimate's height error);
* ``world/elevation_map`` holds the map over time, every ``1 / MAP_RATE`` s and at the run's end, and no
  snapshot holds a cell that the scans fused by its time had not reached;
* the map's edge cells are their own entity, on the risers.
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest
from scipy.spatial import cKDTree

from gaitshift.export.sim_recording import record_simulation
from gaitshift.models.terrain import Terrain
from gaitshift.robots.sensors import DEPTH_CAMERA_SITE
from gaitshift.scenario.terrain import terrain_of
from gaitshift.sim.log import MAP_RATE
from gaitshift.sim.scenario_run import simulate_scenario
from rrd_files import read

pytest.importorskip("rerun.chunk")

SCENARIO = Path(__file__).resolve().parents[2] / "docs" / "perception" / "g1-stairs-up-ahead.yaml"


@pytest.fixture(scope="module")
def perceived(tmp_path_factory):
    """(the run, its recording read back, the true terrain)."""
    run = simulate_scenario(str(SCENARIO), seed=0)  # sim: {terrain: perceived}
    path = tmp_path_factory.mktemp("perceived") / "stairs.rrd"
    record_simulation(run.result, run.trajectory, run.robot, path)
    return run, read(path), terrain_of(run.scenario.terrain)


def surface_distance(p: np.ndarray, truth: Terrain) -> np.ndarray:
    """Distance (P,) m in the x-z plane from points ``p`` (P, 3) to the terrain's surface: its tops
    z(x) and its vertical risers at each break."""
    out = np.abs(p[:, 2] - truth.height(p[:, 0]))
    for b in truth.breaks():
        z = truth.height(np.array([b - 1e-9, b + 1e-9]))
        zc = np.clip(p[:, 2], z.min(), z.max())
        out = np.minimum(out, np.hypot(p[:, 0] - b, p[:, 2] - zc))
    return out


def camera_origins(run, ticks: np.ndarray, key: str) -> np.ndarray:
    """The camera site's position (F, 3) m at ``ticks`` by forward kinematics of the log's ``key``
    configuration (``qpos``: the truth; ``est_qpos``: the controller's estimate)."""
    model = run.robot.model()
    d = mujoco.MjData(model)
    site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, DEPTH_CAMERA_SITE)
    out = np.zeros((len(ticks), 3))
    for n, k in enumerate(ticks):
        d.qpos[:] = run.result.arrays[key][k]
        mujoco.mj_kinematics(model, d)
        out[n] = d.site_xpos[site]
    return out


def test_the_recorded_scans_lie_on_the_true_terrain_within_the_cameras_noise_and_the_estimates_error(perceived):
    run, rec, truth = perceived
    a, cam = run.result.arrays, run.robot.sensors.depth_camera
    rows = sorted((t, np.asarray(v, dtype=float)) for t, v in rec["world/scan"]["Points3D:positions"] if t is not None)
    t_scan = np.array([t for t, _ in rows])
    np.testing.assert_allclose(t_scan, a["scan_t"], atol=1e-6)
    every = round(1.0 / (cam.rate * float(run.result.meta["control_period"])))  # 17 ticks: 29.4 Hz
    np.testing.assert_allclose(np.diff(t_scan), every * 0.002, atol=1e-6)
    assert len(rows) > 200 and max(len(p) for _, p in rows) <= len(cam.rays())
    points = np.concatenate([p for _, p in rows])
    frame = np.repeat(np.arange(len(rows)), [len(p) for _, p in rows])
    ticks = np.searchsorted(a["t"], t_scan - 1e-9)
    est = camera_origins(run, ticks, "est_qpos")
    pose_error = np.linalg.norm(camera_origins(run, ticks, "qpos") - est, axis=1)  # the estimate's, m
    r = np.linalg.norm(points - est[frame], axis=1)
    sigma = cam.noise[0] + cam.noise[1] * r**2  # the camera's stated range noise, m
    off = surface_distance(points, truth) - pose_error[frame]
    assert np.mean(off <= 3 * sigma) > 0.997  # a Gaussian's 3-sigma share
    assert np.all(off <= 6 * sigma)  # no point off the ground: not the robot's body, not a misplaced frame
    assert np.ptp(points[:, 2]) > 0.25  # the scans saw the floor and the landing 0.3 m up


def test_the_recording_holds_every_replans_footholds_moving_onto_the_true_treads(perceived):
    run, rec, truth = perceived
    a = run.result.arrays
    sets = sorted((t, np.asarray(c, dtype=float)) for t, c in rec["world/footsteps"]["Boxes3D:centers"])
    assert len(sets) == len(a["footholds_t"]) > 1 and len(sets) >= run.driver.replans
    np.testing.assert_allclose([t for t, _ in sets], a["footholds_t"], atol=1e-6)
    first, last = sets[0][1], sets[-1][1]
    over_stairs = truth.height(first[:, 0]) > 0.05
    assert over_stairs.any() and np.allclose(first[:, 2], 0.0)  # the blind plan: flat ground
    assert np.abs(last[:, :2] - first[:, :2]).max() > 0.02 and np.abs(last[:, 2] - first[:, 2]).max() > 0.25
    # on the true treads, within 1 cm plus the estimate's own height error: the map is built in the estimate's
    # frame, whose height nothing observes on stairs (seed 0: it drifts 2.6-2.7 cm by the end of the run, and
    # the last footholds stand 1.9-2.1 cm below the true treads)
    drift = np.abs(a["est_qpos"][:, 2] - a["qpos"][:, 2]).max()
    assert np.abs(last[:, 2] - truth.height(last[:, 0])).max() < 0.01 + drift


def timed_rows(rec, entity: str) -> list[tuple[float, np.ndarray]]:
    """The (time s, points (N, 3) m) rows of a point-cloud entity, sorted by time."""
    return sorted((t, np.asarray(v, dtype=float).reshape(-1, 3)) for t, v in rec[entity]["Points3D:positions"])


def test_the_recorded_map_grows_over_time_from_what_the_scans_had_reached(perceived):
    """Each snapshot of the map is the map of its time: every seen cell's centre lies within half a cell's
    diagonal (in xy) of a scan point fused at or before that time. The map as the run ended, logged at
    every snapshot's time, fails this: the first frame reaches x = 2.27 m, the final map 4.1 m."""
    run, rec, _ = perceived
    a = run.result.arrays
    maps, scans = timed_rows(rec, "world/elevation_map"), timed_rows(rec, "world/scan")
    t_map = np.array([t for t, _ in maps])
    expected = np.r_[np.arange(0.0, a["t"][-1] - 1e-9, 1.0 / MAP_RATE), a["t"][-1]]  # the snapshots, the end
    np.testing.assert_allclose(t_map, expected, atol=a["t"][1] - a["t"][0] + 1e-9)
    half_diagonal = float(a["map_resolution"]) * np.sqrt(0.5) + 1e-6
    sizes = []
    for tk, cells in maps:
        seen = np.concatenate([p for t, p in scans if t <= tk + 1e-9])
        gap, _ = cKDTree(seen[:, :2]).query(cells[:, :2])
        assert np.all(gap <= half_diagonal), (tk, gap.max())
        sizes.append(len(cells))
    assert sizes[-1] > 5 * sizes[0]  # seen cells accrue as the robot walks and looks


def test_the_maps_edge_cells_are_their_own_entity_on_the_risers(perceived):
    """Where the robot walked (|y| < 0.5 m, up to 0.5 m past where its pelvis ended), every edge cell is
    within two cells of a true riser and each riser has its edge cells; far off, single noisy returns
    at the camera's range make edges too (not judged here)."""
    run, rec, truth = perceived
    _, edges = timed_rows(rec, "world/elevation_map/edges")[-1]  # the map as the run ended
    _, surface = timed_rows(rec, "world/elevation_map")[-1]
    assert 0 < len(edges) < len(surface)
    walked = (np.abs(edges[:, 1]) < 0.5) & (edges[:, 0] < run.result.arrays["qpos"][-1, 0] + 0.5)
    risers = np.array([b for b in truth.breaks() if b < 2.0])  # the three stairs (the landing ends at 4 m)
    gap = np.abs(edges[walked, 0, None] - risers[None])
    assert np.all(gap.min(axis=1) < 0.08)  # two cells
    assert np.all((gap < 0.08).sum(axis=0) >= 10)
