"""The CoP room of a stance sole (control/cop_room.py): the moment it allows loads the leg's motors up to
their limits (statics, tau = J^T w), and no more; the sole's size bounds it."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from gaitshift.control.cop_room import MIN_ARM, CopRoom
from gaitshift.robots import load_robot
from gaitshift.robots.model import standing_qpos
from gaitshift.sim.plant import build_plant


def _standing(robot: str) -> tuple[object, mujoco.MjData]:
    plant = build_plant(0.002, robot=load_robot(robot))
    data = mujoco.MjData(plant.model)
    data.qpos[:] = standing_qpos(plant)
    mujoco.mj_forward(plant.model, data)
    return plant, data


def _joint_torques(plant: object, data: mujoco.MjData, force: float, moment: np.ndarray) -> np.ndarray:
    """tau = J^T [F e_z; M] at the left sole centre, on the motors (N m)."""
    m = plant.model  # type: ignore[attr-defined]
    centre, _ = plant.sole_frame(data, 0)  # type: ignore[attr-defined]
    jp, jr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
    mujoco.mj_jac(m, data, jp, jr, centre, plant.soles[0].body)  # type: ignore[attr-defined]
    tau = jp.T @ np.array([0.0, 0.0, force]) + jr.T @ moment
    return np.asarray(tau[plant.actuated_dofs])  # type: ignore[attr-defined]


@pytest.mark.parametrize("robot", ["t1", "g1"])
def test_the_largest_moment_puts_one_motor_at_its_limit_and_none_beyond(robot: str) -> None:
    plant, data = _standing(robot)
    room = CopRoom.from_plant(plant, data, (10.0, 10.0))  # a huge sole: the motors decide
    load = plant.mass * 9.81  # type: ignore[attr-defined]
    limit = np.asarray(plant.torque_limit)  # type: ignore[attr-defined]
    _, rot = plant.sole_frame(data, 0)  # type: ignore[attr-defined]
    ex = rot[:, 0] - rot[2, 0] * np.array([0.0, 0.0, 1.0])
    ex /= np.linalg.norm(ex)
    ey = np.cross([0.0, 0.0, 1.0], ex)
    r = room.at(load)
    assert np.all(r > 0.0)
    for shift, axis in ((r[0], ey), (r[1], ex)):  # a CoP shift along x is a moment about y
        for sign in (1.0, -1.0):
            tau = _joint_torques(plant, data, load, sign * load * shift * axis)
            # the joints eq. (2) keeps (arm >= MIN_ARM) stay within their limits, one of them at it
            m = plant.model  # type: ignore[attr-defined]
            centre, _ = plant.sole_frame(data, 0)  # type: ignore[attr-defined]
            jr = np.zeros((3, m.nv))
            mujoco.mj_jac(m, data, None, jr, centre, plant.soles[0].body)  # type: ignore[attr-defined]
            used = np.abs(axis @ jr[:, plant.actuated_dofs]) >= MIN_ARM  # type: ignore[attr-defined]
            assert np.all(np.abs(tau[used]) <= limit[used] + 1e-9)
        worst = max(
            np.max((np.abs(_joint_torques(plant, data, load, sg * load * shift * axis)) / limit)[used])
            for sg in (1.0, -1.0)
        )
        assert worst == pytest.approx(1.0, abs=1e-9)


def test_the_sole_bounds_the_room_and_a_heavier_load_shrinks_it() -> None:
    plant, data = _standing("t1")
    half = (0.11, 0.05)
    room = CopRoom.from_plant(plant, data, half)
    weight = plant.mass * 9.81  # type: ignore[attr-defined]
    light, heavy = room.at(0.2 * weight), room.at(1.5 * weight)
    assert np.allclose(light, half)  # a light load: the sole's edge
    assert np.all(heavy <= light) and heavy[0] < half[0]  # the T1's 20 N m ankles: less than its sole
    assert np.allclose(CopRoom.sole_only(half).at(1e6), half)
