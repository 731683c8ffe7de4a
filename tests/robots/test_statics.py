"""Statics of the standing pose: the least-torque wrench distribution obeys Newton-Euler for the whole
robot (forces sum to m g, moments about the CoM vanish), its joint torques balance gravity in the joint
rows, and a foot link rotated against the world without ``sole_orientation`` is a tilted sole."""

from __future__ import annotations

import math
from importlib import resources

import mujoco
import numpy as np
import pytest

from gaitshift.robots import load_robot
from gaitshift.robots.statics import LEVEL_TOL, standing_statics


def _wrenches(robot):
    """Re-derive the sole wrenches from the torques: w solves J_jᵀ w = g_j - τ and J_bᵀ w = g_b."""
    m = robot.model()
    d = mujoco.MjData(m)
    d.qpos[:] = robot.standing_qpos(m)
    mujoco.mj_forward(m, d)
    st = standing_statics(robot)
    dofs = np.array([m.jnt_dofadr[m.joint(n).id] for n in robot.joint_names])
    rhs = d.qfrc_bias.copy()
    rhs[dofs] -= st.torque
    jp, jr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
    cols, sites = [], [m.site(s).id for s in robot.SOLE_SITES]
    for s in sites:
        mujoco.mj_jacSite(m, d, jp, jr, s)
        cols += [jp.T.copy(), jr.T.copy()]
    Jt = np.hstack(cols)
    w, *_ = np.linalg.lstsq(Jt, rhs, rcond=None)
    return m, d, st, w, np.linalg.norm(Jt @ w - rhs), sites


@pytest.mark.parametrize("name", ["g1", "h1", "berkeley"])
def test_static_torques_and_sole_wrenches_obey_newton_euler(name):
    robot = load_robot(name)
    m, d, st, w, residual, sites = _wrenches(robot)
    weight = robot.mass * -m.opt.gravity[2]
    assert residual < 1e-6 * weight  # τ and some sole wrenches balance gravity in every row
    forces = [w[0:3], w[6:9]]
    assert np.allclose(sum(forces), [0.0, 0.0, weight], atol=1e-6 * weight)
    com = d.subtree_com[0]
    moment = sum(np.cross(d.site_xpos[s] - com, f) for s, f in zip(sites, forces, strict=True)) + w[3:6] + w[9:12]
    assert np.allclose(moment, 0.0, atol=1e-6 * weight)
    assert np.allclose(st.normal_force, [w[2], w[8]], atol=1e-6 * weight)
    assert np.all(st.torque_fraction < 1.0) and np.all(st.tilt < LEVEL_TOL) and st.com_margin > 0


def test_a_rotated_foot_link_without_sole_orientation_is_a_tilted_sole(tmp_path):
    text = (resources.files("gaitshift.robots") / "configs" / "berkeley.yaml").read_text()
    path = tmp_path / "b.yaml"
    path.write_text(
        text.replace("\nsole_orientation: geoms", "\nsole_orientation: body\nstanding_pose: {LL_KFE: 0.5, LR_KFE: 0.5}")
    )
    st = standing_statics(load_robot(path))
    assert np.all(st.tilt > math.radians(20.0))
