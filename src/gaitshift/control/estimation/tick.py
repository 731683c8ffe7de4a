"""The estimator's compiled tick: :class:`StateEstimator.step` as two numba kernels around MuJoCo.

For the InEKF (``inekf``, ``inekf-flat``) with an IMU on the base with the base's axes (the G1), one
tick is (the kernels of :mod:`gaitshift.control.estimation.kernels`; the equations those of the modules
named)::

    sense(...)                 force means and trigger (contact.py), released where the last tick's
                               kinematics ruled a load out (contact_fusion.py), joint filter (joints.py), q and qd
                               into the private MjData
    kinematics.run_mujoco()    mj_kinematics, mj_comPos, 2 mj_jacSite, mj_jacSubtreeCom (kinematics.py)
    settle(phase=0, ...)       points in the IMU frame, InEKF mean step (inekf.py); unless the filter
                               corrects at this tick: world points, slip low-pass (slip.py), lowest sole
                               points, fused contact (contact_fusion.py), quaternion and world rate
    [correction tick]          InvariantEKF.correction_tick (numpy), then settle(phase=1, ...)
    [a sole centre moves]      the support-polygon test of slip.py (Python; rare)

Why: in the closed loop every Python-level numpy call costs ~1.7 us with the caches the physics and
the QP leave cold (docs/estimation.md "Measured cost"); this path makes two kernel calls and the five
MuJoCo calls where the Python path makes ~39 numpy and MuJoCo calls.
The state of the force trigger, the fused contact and the slip low-pass lives here (``ist``, ``fst``,
``recent``, ``rates_lp``); the joint filter, the kinematics and the InEKF keep theirs, shared in place.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gaitshift.control.estimation import kernels as k
from gaitshift.control.estimation.contact import ContactDetector
from gaitshift.control.estimation.contact_fusion import (
    CUSUM_THRESHOLD,
    LAND_SPEED,
    LIFT_HEIGHT,
    SWING_SPEED,
    ContactFusion,
)
from gaitshift.control.estimation.inekf import InvariantEKF
from gaitshift.control.estimation.joints import JointVelocityFilter
from gaitshift.control.estimation.kinematics import LegKinematics
from gaitshift.control.estimation.slip import SlipDetector
from gaitshift.control.estimation.types import FLAG_PAIRS, EstimatedState, new_estimated_state


class CompiledTick:
    """:meth:`StateEstimator.step` on the kernels (module docstring), for an InEKF and an IMU with the
    base's axes; built from the estimator's parts, whose parameters (and, for the joint filter, the
    kinematics and the filter, arrays) it uses."""

    def __init__(
        self, kin: LegKinematics, joints: JointVelocityFilter, filt: InvariantEKF, contact: ContactDetector,
        fusion: ContactFusion, slip: SlipDetector, points: tuple[np.ndarray, np.ndarray], dt: float,
    ) -> None:  # fmt: skip
        if fusion.window != contact.window:
            raise ValueError("the force trigger and the fused contact average the same window")
        self.kin, self.joints, self.filter, self.slip = kin, joints, filt, slip
        self.nj = nj = kin.n_joints
        self.size = 2 * nj + 31
        self.ist = np.zeros(k.IST_SIZE, np.int64)
        self.fst = np.zeros(k.FST_SIZE)
        self.recent = np.zeros((2, contact.window))
        self.means = np.zeros(2)
        self.rates_lp = np.zeros((2, 3 + nj))
        self.trigger = np.array([contact.on_force, contact.off_force, float(contact.debounce)])
        m = filt.mean_arrays(dt)
        fuse = [fusion.on_force, fusion.off_force, fusion.cusum_gain, fusion.cusum_half, fusion.near, fusion.still]
        rules = [CUSUM_THRESHOLD, LIFT_HEIGHT, SWING_SPEED, LAND_SPEED, fusion.flight_on, fusion.flight_off]
        self.par = np.array([dt, float(m.every), slip.alpha, slip.slip_speed, *fuse, *rules])
        n = max(len(p) for p in points)
        self.pts = np.array([np.concatenate([p, np.repeat(p[:1], n - len(p), axis=0)]) for p in points])
        d = kin.data
        self.fixed = (self.par, self.ist, self.fst, self.means)
        self.kin_arrays = (kin.sole_ids.astype(np.int64), d.site_xpos, d.site_xmat, kin.com_view, kin.p_s)
        self.kin_arrays2 = (kin.jac, kin.qvel, kin.points_aug, kin.vel)
        self.mean = m
        self.no_plan = np.zeros(2, bool)
        self.reset((False, False), started=False)

    def reset(self, contact: Any, started: bool = True) -> None:
        """The stance and fused flags (2,), no force history, no CUSUM, no ground level, the slip
        low-pass at rest; ``started``: the joint filter was reset (else it starts at the first reading)."""
        self.ist[:] = 0
        self.ist[k.I_STANCE : k.I_STANCE + 2] = self.ist[k.I_FUSED : k.I_FUSED + 2] = [bool(c) for c in contact]
        self.ist[k.I_STARTED] = int(started)
        self.fst[:] = 0.0
        self.fst[k.F_GROUND] = np.nan
        self.fst[k.F_STAND : k.F_STAND + 2] = np.nan
        self.rates_lp[:] = 0.0

    def landing(self) -> np.ndarray:
        """(2,) bool: the soles on by a landing alone (``ist[I_LAND]``, contact_fusion.py)."""
        out: np.ndarray = self.ist[k.I_LAND : k.I_LAND + 2] != 0
        return out

    def _settle(self, phase: int, imu: Any, normal: np.ndarray, planned: Any, out: np.ndarray) -> int:
        m, (par, ist, fst, means), (idx, xpos, xmat, com, p_s), (jac, qvel, aug, vel) = (
            self.mean, self.fixed, self.kin_arrays, self.kin_arrays2,
        )  # fmt: skip
        plan, has_plan = (self.no_plan, False) if planned is None else (planned, True)
        return int(
            k.settle(
                phase, plan, has_plan, imu.gyro, imu.accel, par, ist, fst, means, normal, idx, xpos, xmat, com,
                p_s, jac, qvel, aug, vel, m.quat, m.rot9, m.vec, m.bias, m.step, m.gravity_step, m.offset,
                m.ticks, self.rates_lp, self.pts, out,
            )
        )  # fmt: skip

    def step(self, imu: Any, joints: Any, forces: Any, planned: np.ndarray | None) -> EstimatedState:
        """One tick (module docstring): readings in, the :class:`EstimatedState` out."""
        nj, normal, out = self.nj, forces.normal, np.empty(self.size)
        j = self.joints
        k.sense(normal, joints.q, joints.qd, self.trigger, self.ist, self.recent, self.means, j.a, j.gain, j.state,
              self.kin.data.qpos, self.kin.qvel, out)  # fmt: skip
        body = self.kin.run_mujoco()
        code = self._settle(0, imu, normal, planned, out)
        if code & k.CORRECT:
            flags = FLAG_PAIRS[bool(code >> k.FILTER_STANCE & 1), bool(code >> k.FILTER_STANCE & 2)]
            self.filter.correction_tick(body.feet, flags)
            code = self._settle(1, imu, normal, planned, out)
        xv = out[2 * nj : 2 * nj + 24].reshape(8, 3)
        slip = self._support(code, body) if code & (3 * k.SUPPORT) else FLAG_PAIRS[False, False]
        o = 2 * nj + 24
        return new_estimated_state(
            xv[3], out[o : o + 4], xv[7], out[o + 4 : o + 7], out[0:nj], out[nj : 2 * nj],
            FLAG_PAIRS[bool(code & 1), bool(code & 2)], FLAG_PAIRS[bool(code & 4), bool(code & 8)], slip,
            xv[4:6], xv[2], xv[6], self.filter.cov_trace,
        )  # fmt: skip

    def _support(self, code: int, body: Any) -> np.ndarray:
        """The support-polygon test of slip.py for the soles whose centre moves (``code`` bits 4, 5)."""
        rot, flags = self.filter.rot, [False, False]
        speed = self.fst[k.F_SPEED : k.F_SPEED + 2].tolist()
        for i in (0, 1):
            if code & (k.SUPPORT << i):
                rates = self.rates_lp[i]
                omega = rot.dot(rates[:3] + self.kin.sole_rate(i, rates[3:]))
                vx, vy = self.fst[k.F_VEL_LP + 2 * i : k.F_VEL_LP + 2 * i + 2].tolist()
                speed[i] = self.fst[k.F_SPEED + i] = self.slip.support_speed(
                    i, vx, vy, omega, rot.dot(body.feet.rot[i])
                )
                flags[i] = speed[i] > self.slip.slip_speed
        return FLAG_PAIRS[self.slip.resolve(flags, speed)]
