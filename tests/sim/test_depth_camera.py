"""The simulated depth camera sees the ground and only the ground: an exact camera's points, put back
in the world with the site's true pose, lie on the floor and on a bump's top; frames come at the
camera's rate; noise and dropout have the stated size."""

from __future__ import annotations

from dataclasses import replace

import mujoco
import numpy as np

from gaitshift.robots import load_robot
from gaitshift.robots.sensors import DEPTH_CAMERA_SITE
from gaitshift.sim.bumps import Bump
from gaitshift.sim.depth_camera import DepthCameraSim
from gaitshift.sim.plant import build_plant

DT = 0.002


def _standing(bumps=()):
    plant = build_plant(DT, "g1", bumps=bumps)
    m = plant.model
    d = mujoco.MjData(m)
    d.qpos[:] = plant.robot.standing_qpos(m)
    d.qpos[2] = 0.76
    mujoco.mj_forward(m, d)
    return plant, m, d


def _world(m, d, pts):
    site = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, DEPTH_CAMERA_SITE)
    return d.site_xpos[site] + pts @ d.site_xmat[site].reshape(3, 3).T


def test_an_exact_camera_sees_the_floor_and_a_bumps_top_at_its_rate():
    cam = replace(load_robot("g1").sensors.depth_camera, noise=(0.0, 0.0), dropout=0.0)
    bump = Bump(x=0.6, height=0.08, length=0.3)
    _, m, d = _standing((bump,))
    sim = DepthCameraSim(m, cam, DT, seed=0)
    pts = sim.read(d, 0)
    assert pts is not None and pts.shape[1] == 3 and len(pts) > 0.5 * len(cam.rays())
    w = _world(m, d, pts)
    on_top = (w[:, 0] > bump.x + 1e-6) & (w[:, 0] < bump.x + bump.length - 1e-6) & (np.abs(w[:, 1]) < 0.5)
    assert on_top.any() and np.allclose(w[on_top, 2], bump.height, atol=1e-9)
    off = (w[:, 0] < bump.x - 0.01) | (w[:, 0] > bump.x + bump.length + 0.01)
    assert np.allclose(w[off, 2], 0.0, atol=1e-9)
    r = np.linalg.norm(pts, axis=1)
    assert r.min() >= cam.range[0] and r.max() <= cam.range[1]
    every = round(1 / (cam.rate * DT))
    assert [k for k in range(3 * every) if sim.read(d, k) is not None] == [0, every, 2 * every]


def test_range_noise_and_dropout_have_their_stated_size():
    """Over 40 frames of a still robot: the std of r~ - r is sigma_0 + k r^2 (within 10 %) and the lost
    share is the dropout (within 1 %)."""
    exact = replace(load_robot("g1").sensors.depth_camera, noise=(0.0, 0.0), dropout=0.0)
    noisy = replace(exact, noise=(0.003, 0.01), dropout=0.1)
    _, m, d = _standing()
    exact_pts = DepthCameraSim(m, exact, DT, 0).read(d, 0)
    truth = np.linalg.norm(exact_pts, axis=1)
    exact_dirs = exact_pts / truth[:, None]
    sim = DepthCameraSim(m, noisy, DT, 1)
    kept, rel = 0, []
    for k in range(40):
        pts = sim.read(d, k * sim.every)
        kept += len(pts)
        r = np.linalg.norm(pts, axis=1)
        rays = pts / r[:, None]  # the exact range of each kept pixel: matched by ray direction
        j = np.argmax(rays @ exact_dirs.T, axis=1)
        r0 = truth[j]
        rel.append((r - r0) / (noisy.noise[0] + noisy.noise[1] * r0**2))
    z = np.concatenate(rel)
    assert abs(np.std(z) - 1.0) < 0.1
    assert abs(1 - kept / (40 * len(truth)) - noisy.dropout) < 0.01
