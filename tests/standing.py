"""The simulated G1 standing still on the floor: the common starting state of controller and sim tests."""

from __future__ import annotations

import mujoco
import numpy as np

from gaitshift.robots.model import standing_qpos
from gaitshift.sim.plant import build_plant


def standing(control_period=0.002):
    """(plant, MjData after ``mj_forward`` + ``mj_subtreeVel``, standing qpos (nq,), sole centres (2, 3))."""
    plant = build_plant(control_period)
    m = plant.model
    d = mujoco.MjData(m)
    q0 = standing_qpos(plant)
    d.qpos[:] = q0
    mujoco.mj_forward(m, d)
    mujoco.mj_subtreeVel(m, d)
    feet = np.array([plant.sole_frame(d, s)[0] for s in (0, 1)])
    return plant, d, q0, feet
