"""The controller's warm-up before a real-time run: the process's first ticks are slow.

Measured on this machine: a fresh process's first controller ticks take 40-540 ms (lazy imports and
first-call set-up of the planner and the QP, shared by every controller of the process), a second
controller's first ticks 8-25 ms, later ticks about 1 ms. :func:`warm_up` ticks a throwaway controller of
the same scenario on a still frame of its start pose (:func:`still_frame`) before the run, so that the
first locomotion ticks of the real one do not stall the 2 ms loop for half a second.
"""

import time
from dataclasses import replace

import mujoco
import numpy as np

from gaitshift.control.controller import Controller
from gaitshift.control.frames import SensorFrame
from gaitshift.dds.gravity import standing_torques

__all__ = ["still_frame", "warm_up"]

GRAVITY = np.array([0.0, 0.0, 9.81])


def still_frame(ctrl: Controller, t: float) -> SensorFrame:
    """The frame at ``t`` s of ``ctrl``'s robot standing still in its start pose: the IMU level as the
    pose has it (the accelerometer reading gravity's reaction, m/s^2), the joints at rest, the motors
    carrying the weight (:func:`gaitshift.dds.gravity.standing_torques`, N m)."""
    m = ctrl.robot.model
    d = mujoco.MjData(m)
    q0 = ctrl.initial_qpos()
    d.qpos[:] = q0
    mujoco.mj_forward(m, d)
    quat = np.array([1.0, 0.0, 0.0, 0.0])
    R = np.eye(3)
    if ctrl.imu_site is not None:
        R = d.site(ctrl.imu_site).xmat.reshape(3, 3).copy()
        mujoco.mju_mat2Quat(quat, R.ravel())
    adr = [int(m.joint(name).qposadr[0]) for name in ctrl.motor_names]
    n = len(adr)
    return SensorFrame(
        t=t,
        imu_quat=quat,
        imu_gyro=np.zeros(3),
        imu_acc=R.T @ GRAVITY,
        q=q0[adr],
        dq=np.zeros(n),
        tau_est=standing_torques(ctrl.robot, q0),
    )


def warm_up(ctrl: Controller, ticks: int = 20) -> float:
    """Tick ``ctrl`` (a throwaway: its state is spent) ``ticks`` times on :func:`still_frame`; the wall
    time it took, s."""
    start = time.perf_counter()
    frame = still_frame(ctrl, 0.0)
    for k in range(ticks):
        ctrl.tick(replace(frame, t=k * ctrl.period))
    return time.perf_counter() - start
