"""The elevation map fuses like a Kalman filter of a constant per cell (eq. (1)), ages by q dt
(eq. (2)), keeps what it saw when it moves with the robot, finds a step's edge where the step is, and
the perceiver puts camera-frame points where the camera pose says (eq. (1) of perceiver.py)."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from gaitshift.control.perception import ElevationMap, MapSettings, Perceiver
from gaitshift.robots import load_robot
from gaitshift.robots.sensors import DEPTH_CAMERA_SITE

R = 0.05


def test_points_of_one_cell_fuse_as_an_inverse_variance_mean_then_update_the_prior():
    m = ElevationMap(MapSettings(size=1.0, resolution=R))
    m.recenter(np.zeros(2))
    pts = np.array([[0.01, 0.01, 0.10], [0.02, 0.03, 0.13]])
    var = np.array([1e-4, 4e-4])
    assert m.fuse(pts, var) == 2
    w = 1 / var
    h, p = m.lookup(np.array([[0.0, 0.0]]))
    assert h[0] == pytest.approx(np.sum(w * pts[:, 2]) / w.sum(), rel=1e-12)
    assert p[0] == pytest.approx(1 / w.sum(), rel=1e-12)
    m.fuse(np.array([[0.04, 0.04, 0.2]]), np.array([2e-4]))  # the Kalman update of that estimate
    p2 = 1 / (w.sum() + 1 / 2e-4)
    h2, q2 = m.lookup(np.array([[0.0, 0.0]]))
    assert q2[0] == pytest.approx(p2, rel=1e-12)
    assert h2[0] == pytest.approx(p2 * (h[0] / p[0] + 0.2 / 2e-4), rel=1e-12)
    assert np.isinf(m.lookup(np.array([[0.3, 0.3], [9.0, 9.0]]))[1]).all()  # unseen, outside


def test_aging_adds_q_dt_to_known_cells_only():
    m = ElevationMap(MapSettings(size=1.0, resolution=R, process_noise=2e-3))
    m.recenter(np.zeros(2))
    m.fuse(np.array([[0.0, 0.0, 0.0]]), np.array([1e-4]))
    m.age(0.5)
    assert m.lookup(np.array([[0.0, 0.0]]))[1][0] == pytest.approx(1e-4 + 1e-3)
    assert m.known.sum() == 1


def test_recentering_keeps_a_seen_cell_at_its_world_place_and_forgets_what_leaves_the_grid():
    m = ElevationMap(MapSettings(size=1.0, resolution=R))
    m.recenter(np.zeros(2))
    m.fuse(np.array([[0.12, -0.07, 0.3], [-0.45, 0.0, 0.1]]), np.array([1e-4, 1e-4]))
    m.recenter(np.array([0.33, 0.21]))
    h, p = m.lookup(np.array([[0.12, -0.07], [-0.45, 0.0]]))
    assert h[0] == pytest.approx(0.3) and np.isfinite(p[0])
    assert np.isinf(p[1])  # now outside the grid
    centre = m.centres()[m.n // 2, m.n // 2]
    assert np.all(np.abs(centre - [0.33, 0.21]) <= R)


def test_a_step_edge_is_found_on_the_two_cells_either_side_of_it():
    m = ElevationMap(MapSettings(size=2.0, resolution=R))
    m.recenter(np.zeros(2))
    xy = m.centres().reshape(-1, 2)
    z = np.where(xy[:, 0] > 0.3, 0.15, 0.0)  # a 15 cm step up at x = 0.3
    m.fuse(np.column_stack([xy, z]), np.full(len(z), 1e-6))
    edges = m.edges(step=0.05)
    x = m.centres()[..., 0]
    assert np.all(np.abs(x[edges] - 0.3) < R) and edges.sum() == 2 * m.n
    assert not m.edges(step=0.2).any()


def test_the_perceiver_places_camera_points_with_the_camera_pose_of_the_controllers_model():
    """Points on the plane z = 0.07 seen from the G1's head camera (given in the camera frame) land in
    the map at 0.07 m, where the rays meet that plane."""
    cfg = load_robot("g1")
    model = cfg.model()
    d = mujoco.MjData(model)
    d.qpos[:] = cfg.standing_qpos(model)
    d.qpos[2] = 0.75
    mujoco.mj_forward(model, d)
    site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, DEPTH_CAMERA_SITE)
    cam = cfg.sensors.depth_camera
    rays = cam.rays()
    rot, o = d.site_xmat[site].reshape(3, 3), d.site_xpos[site]
    world_dir = rays @ rot.T
    r = (0.07 - o[2]) / world_dir[:, 2]
    ok = (r > 0) & (r < cam.range[1])
    per = Perceiver(model, cam, MapSettings(size=4.0, resolution=R))
    per.frame(0.0, r[ok, None] * rays[ok], d)
    hits = o + r[ok, None] * world_dir[ok]
    h, p = per.map.lookup(hits[:, :2])
    seen = np.isfinite(p)
    assert seen.mean() > 0.9 and np.allclose(h[seen], 0.07, atol=1e-9)
    assert np.all(hits[:, 0] > d.qpos[0])  # the camera looks ahead


def test_the_controllers_map_is_built_from_the_frames_points_alone():
    """The truth barrier: a controller ticked with frames whose depth points show a 10 cm plateau ahead
    (while nothing in any world is there) maps the plateau, and frames without points leave it be."""
    from gaitshift.control.controller import Controller
    from gaitshift.control.frames import SensorFrame

    c = Controller.from_scenario("g1-walk")
    m, cam = c.robot.model, c.robot.robot.sensors.depth_camera
    d = mujoco.MjData(m)
    d.qpos[:] = c.initial_qpos()
    mujoco.mj_forward(m, d)
    site = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, DEPTH_CAMERA_SITE)
    rot, o = d.site_xmat[site].reshape(3, 3), d.site_xpos[site]
    rays = cam.rays()
    r = (0.10 - o[2]) / (rays @ rot.T)[:, 2]
    pts = r[r > 0, None] * rays[r > 0]
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, d.site_xmat[m.site(c.imu_site).id])
    up = d.site_xmat[m.site(c.imu_site).id].reshape(3, 3).T @ np.array([0.0, 0.0, 9.81])
    idx = m.jnt_qposadr[m.actuator_trnid[:, 0]]
    n = m.nu
    base = {"imu_quat": quat, "imu_gyro": np.zeros(3), "imu_acc": up, "q": d.qpos[idx], "dq": np.zeros(n),
            "tau_est": np.zeros(n)}  # fmt: skip
    c.tick(SensorFrame.checked(n, t=0.0, **base))
    assert c.perceiver is not None and not c.perceiver.map.known.any()
    c.tick(SensorFrame.checked(n, t=0.002, depth_points=pts, **base))
    known = c.perceiver.map.known
    assert known.sum() > 100 and np.allclose(c.perceiver.map.height[known], 0.10, atol=0.01)
