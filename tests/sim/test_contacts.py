"""Foot contacts, ground reaction forces and the fall test.

Oracle for the forces: MuJoCo's own external-force bookkeeping (``mj_rnePostConstraint`` ->
``cfrc_ext``, the total contact force on each body in the world frame), a different code path from
the per-contact ``mj_contactForce`` the sensor sums.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from gaitshift.control.wbc import TickReference, WholeBodyController
from gaitshift.robots.model import standing_qpos
from gaitshift.sim.contacts import FALL_HEIGHT_FRACTION, ContactSensor, FootContacts, fall_reason
from gaitshift.sim.plant import build_plant
from standing import standing


@pytest.fixture(scope="module")
def plant():
    return build_plant(0.002)


def test_ground_reaction_forces_of_a_standing_robot_are_the_contact_forces_on_its_soles():
    plant, d, q0, feet = standing()
    m = plant.model
    ref = TickReference.still(d.subtree_com[0].copy(), feet)
    ctrl = WholeBodyController(plant, q0)
    sensor = ContactSensor(plant)
    for _ in range(250):  # 0.5 s of standing
        mujoco.mj_forward(m, d)
        mujoco.mj_subtreeVel(m, d)
        d.ctrl[:] = ctrl.compute(d, ref)[0]
        mujoco.mj_step(m, d)
    mujoco.mj_forward(m, d)
    contacts = sensor.read(d)
    assert contacts.touching.tolist() == [True, True] and contacts.foreign is None
    mujoco.mj_rnePostConstraint(m, d)
    for s in (0, 1):
        np.testing.assert_allclose(contacts.grf[s], d.cfrc_ext[plant.soles[s].body, 3:], atol=1e-6)
    assert contacts.grf[:, 2].sum() == pytest.approx(plant.mass * 9.81, rel=0.02)


def test_a_robot_lying_on_the_floor_is_a_fall_named_by_the_body(plant):
    m = plant.model
    d = mujoco.MjData(m)
    d.qpos[:] = standing_qpos(plant)
    d.qpos[2] = 0.08
    d.qpos[3:7] = (np.cos(np.pi / 4), np.sin(np.pi / 4), 0.0, 0.0)  # rolled 90 degrees onto its side
    mujoco.mj_forward(m, d)
    contacts = ContactSensor(plant).read(d)
    assert contacts.foreign is not None
    assert fall_reason(contacts, float(d.qpos[2]), 0.75) == f"{contacts.foreign} touched the floor"


def test_pelvis_below_sixty_percent_of_its_height_is_a_fall():
    clear = FootContacts(np.array([True, True]), np.zeros((2, 3)), None)
    assert FALL_HEIGHT_FRACTION == 0.6
    assert fall_reason(clear, 0.61 * 0.75, 0.75) is None
    assert fall_reason(clear, 0.59 * 0.75, 0.75) == "pelvis below 60% of its initial height"
