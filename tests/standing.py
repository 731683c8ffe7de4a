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


def rest_frame(ctrl, t=0.0, foot_force=True):
    """The SensorFrame a robot at rest in ``ctrl``'s start pose reports at ``t`` s (exact sensors; each sole
    carrying half the weight when ``foot_force``, else no foot force)."""
    from gaitshift.control.frames import SensorFrame

    m = ctrl.robot.model
    d = mujoco.MjData(m)
    d.qpos[:] = ctrl.initial_qpos()
    mujoco.mj_forward(m, d)
    idx = m.jnt_qposadr[m.actuator_trnid[:, 0]]
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, d.site_xmat[m.site(ctrl.imu_site).id])
    up = d.site_xmat[m.site(ctrl.imu_site).id].reshape(3, 3).T @ np.array([0.0, 0.0, 9.81])
    n = m.nu
    force = np.full(2, ctrl.robot.mass * 9.81 / 2) if foot_force else None
    return SensorFrame.checked(
        n, t=t, imu_quat=quat, imu_gyro=np.zeros(3), imu_acc=up, q=d.qpos[idx], dq=np.zeros(n),
        tau_est=np.zeros(n), foot_force=force,
    )  # fmt: skip
