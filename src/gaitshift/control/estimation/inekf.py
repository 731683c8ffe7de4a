"""Contact-aided invariant EKF with IMU biases (Hartley et al., RSS 2018 and IJRR 2020).

State (world frame ``W``, IMU frame ``I``), a point of ``SE_4(3)`` plus the biases::

    X = [[R, v, p, d_L, d_R], [0, I_4]],   theta = (b_g, b_a)
    R: orientation of I in W;  v, p: IMU velocity and position;  d_L, d_R: stance contact points.

Error: right-invariant ``eta = X X_hat^{-1} = Exp(xi)`` with ``xi = (xi_R, xi_v, xi_p, xi_dL, xi_dR)``
(15,) and the bias error ``zeta = theta - theta_hat`` (6,): the 21-dim error of the "imperfect IEKF"
(Hartley 2020, §V-B). IMU model ``w~ = w + b_g + n_g``, ``a~ = a + b_a + n_a`` (``a`` = specific force).

Process (Hartley 2018, eqs. 4 and 21-23, with the bias columns of Hartley 2020, eq. 33)::

    R+ = R Exp((w~ - b_g) dt),  v+ = v + (R (a~ - b_a) + g) dt,  p+ = p + v dt + (R (a~ - b_a) + g) dt^2/2
    d/dt xi = A xi + Ad_X_hat n,       A = [[0,   0, 0, 0, -R      , 0 ],
                                              [g^, 0, 0, 0, -v^ R   , -R],
                                              [0,  I, 0, 0, -p^ R   , 0 ],
                                              [0,  0, 0, 0, -d_i^ R , 0 ],
                                              [0,  0, 0, 0,  0      , 0 ]]
    Phi = I + A dt + [g^ dt^2/2 in (p, R)],   P+ = Phi P Phi^T + Q dt,
    Q dt = dt (s_g^2 M M^T + diag(0, s_a^2 I, 0, s_c^2 I, s_c^2 I, s_bg^2 I, s_ba^2 I)),
    M = [R; v^R; p^R; d_L^R; d_R^R] (the gyro-noise column of Ad_X, since R R^T = I).

Measurement of a stance foot i (Hartley 2018, eq. 27, right-invariant form ``Y = X^{-1} b``)::

    y = R^T (d_i - p) + n_y,   innovation z = R_hat y - (d_hat_i - p_hat) = xi_di - xi_p + R_hat n_y,
    H = [0, 0, -I, I_(d_i), 0],  N = (var_i + foot_floor^2) I    (isotropic, so R N R^T = N),
    K = P H^T (H P H^T + N)^{-1},  X+ = Exp(K z)[:15] X,  theta+ = theta + (K z)[15:],  P+ = (I - K H) P.

A foot that touches down joins with ``d = p + R y`` and ``P_d* = P_p*``, ``P_dd = P_pp + N``
(Hartley 2018, §VI-D); a foot that lifts off stops being measured (its rows no longer matter, which
equals marginalising it). The state keeps a fixed size (21) so no array is reallocated per tick.

The stance point ``y`` is the sole's centre ``y_c``, or the point under its centre of pressure ``r_i``
(sole frame, :meth:`InvariantEKF.place_contacts`), ``y = y_c + R_f r_i`` (``R_f``: the sole in the IMU
frame), about which a rolling sole turns (docs/deploy.md, "The stance point at the centre of pressure");
a CoP that moves by ``dr`` on a stance sole moves the stored point, ``d_i <- d_i + R R_f dr``.

A known flat floor (``floor``, m) adds the height of each flat stance sole as a measurement, after the
foot corrections of the same tick (:mod:`gaitshift.control.estimation.floor`).

Multi-rate: the mean follows the IMU every tick; the covariance is propagated with ``dt`` replaced by
``Delta = correct_every dt`` (linearised at the state of the correcting tick), and the corrections and
contact changes happen on those ticks only (``FilterTuning.correct_every``, docs/estimation.md).

Local origin. Absolute position and the yaw about any vertical axis are unobservable, and with the
right-invariant error a yaw correction ``Exp(xi_R)`` rotates ``p`` and ``d_i`` about the origin of the
frame they are expressed in: 1 cm of lateral jump per 0.01 rad of yaw correction per metre from
that origin (measured on the G1 running 1.3 m from the start: 12 cm jumps of the position estimate
at 0.09 rad yaw corrections). The filter therefore keeps ``p`` and ``d_i`` relative to an origin
``o`` that it moves to the IMU position at every correction tick (the world position is ``o + p``).
Moving the origin by ``c`` is the change of error coordinates

    xi_p' = xi_p - c^ xi_R,   xi_di' = xi_di - c^ xi_R   (p = p_hat + xi_R^ p_hat + xi_p to first order),
    P' = T P T^T,   T = I + [-c^ in the (p, R) and (d_i, R) blocks],

exact for the linearised error, so the filter's consistency is unchanged; yaw corrections then turn
the state about the robot instead of about the start point.

Flat feet (``flat_feet=True``, after Ramadoss et al., IROS 2022, "Comparing EKF-based estimators for
humanoids with flat feet"): each stance sole also keeps its world orientation ``Z_i`` (error
``Z = Exp(xi_Z) Z_hat``, random walk ``s_zr``), measured through the sole orientation ``R_f`` the
kinematics give in the IMU frame::

    R_f = R^T Z_i Exp(n_r),   z_r = Log(R_hat R_f Z_hat_i^T) = xi_Zi - xi_R + n_r,   H_r = [-I, .., I_(Z_i), ..]

A sole that touches down joins with ``Z = R R_f`` and ``P_Z* = P_R*``. The error then has 27
components (R, v, p, d_L, d_R, Z_L, Z_R, b_g, b_a). A flat sole makes the yaw-rate bias observable on
one foot (a point contact does not: a yaw-rate bias and a velocity error move the predicted point
alike, to first order).
"""

from __future__ import annotations

from typing import NamedTuple

import mujoco
import numpy as np
from scipy.linalg.lapack import dposv

from gaitshift.control.estimation.calibration import GyroCalibration
from gaitshift.control.estimation.floor import floor_correction
from gaitshift.control.estimation.inekf_terms import CorrectionPattern, StancePoints, diagonal_view, move_origin
from gaitshift.control.estimation.lie import SKEW, exp_blocks, log_rot, quat_exp, quat_of_mat
from gaitshift.control.estimation.tuning import FilterTuning
from gaitshift.control.estimation.types import BaseState, FootKinematics, ImuReading, new_base_state

SYMMETRISE_EVERY = 16  # ticks between P <- (P + P^T) / 2 (round-off hygiene)


class MeanArrays(NamedTuple):
    """The filter's arrays the mean step reads and writes (:meth:`InvariantEKF.mean_arrays`)."""

    quat: np.ndarray  # (4,) orientation R of the IMU (w, x, y, z)
    rot9: np.ndarray  # (9,) R row-major
    vec: np.ndarray  # (5, 6): columns 0:3 rows v, p, d_L, d_R (positions from the origin), a_w
    bias: np.ndarray  # (6,) b_g, b_a
    step: np.ndarray  # (2, 5) [v, p] <- step @ [v, p, d_L, d_R, a_w]
    gravity_step: np.ndarray  # (2, 3) [dt; dt^2 / 2] g^T
    offset: np.ndarray  # (2, 3) [0; o]: [v; p] + offset is the world [v; p]
    ticks: np.ndarray  # (1,) int64 tick counter
    every: int  # ticks between corrections


class InvariantEKF:
    """Right-invariant EKF on SE_4(3) with gyro and accelerometer biases (module docstring).

    Args:
        tuning: noise model (``FilterTuning``); defaults if None.
        gravity: g, m/s^2 (world gravity is ``(0, 0, -g)``).
        flat_feet: also keep and measure the stance soles' orientations (module docstring).
    """

    def __init__(self, tuning: FilterTuning | None = None, gravity: float = 9.81, flat_feet: bool = False):
        self.tuning = t = tuning if tuning is not None else FilterTuning()
        self.flat_feet = bool(flat_feet)
        self.nx = nx = 27 if self.flat_feet else 21
        self._ib = ib = nx - 6  # first bias index
        self.gravity = np.array([0.0, 0.0, -gravity])
        self._quat = np.array([1.0, 0.0, 0.0, 0.0])
        self._rot9 = np.eye(3).ravel()
        self.rot = self._rot9.reshape(3, 3)  # view, kept equal to the quaternion
        # rows v, p, d_L, d_R, a_w (world); columns 0:3 the vectors, 3:6 the correction rho (rows 0:4)
        self._buf = np.zeros((5, 6))
        self._vec = self._buf[:, 0:3]
        self._vp = self._buf[0:2, 0:3]  # v, p
        self._acc_w = self._buf[4, 0:3]
        self._rho = self._buf[0:4, 3:6]
        self._offset = np.zeros((2, 3))  # [0, o]: [v, p] + offset is the returned [v, o + p]
        self._origin = self._offset[1]  # o: p, d_L, d_R are relative to it (module docstring)
        self._bias = np.zeros(6)  # b_g, b_a
        self._bias_g, self._bias_a = self._bias[0:3], self._bias[3:6]
        self._bias_out_g, self._bias_out_a = self._bias_g.copy(), self._bias_a.copy()
        self._cov_trace = 0.0
        self._every = int(t.correct_every)
        self._dc = 0.0
        self._gravity_step = np.zeros((2, 3))  # [dt; dt^2 / 2] g^T
        self._zquat = np.zeros((2, 4))  # stance-sole orientations Z_L, Z_R (flat feet)
        self._zrot = np.zeros((2, 3, 3))
        self._zrot9 = self._zrot.reshape(2, 9)
        # covariance, bordered by the gyro-noise block: P_aug = [[P, 0], [0, s_g^2/dt I_3]]
        self._cov_aug = np.zeros((nx + 3, nx + 3))
        self.cov = self._cov_aug[0:nx, 0:nx]
        self._cov_diag = diagonal_view(self._cov_aug)[0:nx]
        # Phi bordered by the gyro-noise input column M dt (= the gyro-bias column of Phi)
        self._phi = np.zeros((nx, nx + 3))
        self._phi[:, 0:nx] = np.eye(nx)
        self._phi_t = self._phi.T
        self._phi_rot = self._phi[0:3, ib : ib + 3]  # -R dt
        self._phi_skew = self._phi[3:15, ib : ib + 3].reshape(4, 3, 3)  # -x^ R dt for x = v, p, d_L, d_R
        self._phi_acc = self._phi[3:6, ib + 3 : ib + 6]  # -R dt
        self._phi_gyro = self._phi[0:15, ib : ib + 3]
        self._phi_noise = self._phi[0:15, nx : nx + 3]
        self._mean_step = np.zeros((2, 5))  # [v, p] <- mean_step @ [v, p, d_L, d_R, a_w]
        self._dt = -1.0
        self._qdiag = np.zeros(nx)
        self._floor2 = np.array([t.foot_floor**2] * 2 + [t.foot_rot_floor**2] * 2)
        self._in_state = [False, False]
        self._points = StancePoints()  # r_i (module docstring)
        self.ticks = np.zeros(1, np.int64)  # ticks since construction (an array: the compiled tick counts too)
        self._exp_mat = np.zeros((6, 3))  # [Exp(phi)^T ; J_l(phi)^T]
        self._exp_flat = self._exp_mat.reshape(18)
        self._dquat = np.empty(4)
        self._zdquat = np.empty(4)
        self._noise_of: np.ndarray | None = None  # the variance array the cached noise came from
        #: the height, m, of a flat floor known under the stance soles (:mod:`~gaitshift.control.estimation.floor`)
        self.floor: float | None = None
        keys = ((True, False), (False, True), (True, True))
        self._patterns = {key: CorrectionPattern(key, nx, self.flat_feet) for key in keys}
        self.reset(np.eye(3), np.zeros(3))

    # ------------------------------------------------------------------ set-up
    def reset(
        self, rot: np.ndarray, pos: np.ndarray, vel: np.ndarray | None = None, gyro_bias: GyroCalibration | None = None
    ) -> None:
        """Restart at IMU orientation ``rot`` (3, 3), position (3,) and velocity (3,) (zero if None),
        the biases at zero (their prior mean) or the gyro bias at a standstill calibration
        ``gyro_bias`` (:class:`~gaitshift.control.estimation.calibration.GyroCalibration`: its mean and
        std); the covariance restarts from the tuning's priors and no foot is in the state."""
        t = self.tuning
        self._quat[:] = quat_of_mat(rot)
        mujoco.mju_quat2Mat(self._rot9, self._quat)
        self._vec[0] = 0.0 if vel is None else vel
        self._origin[:] = pos
        self._vec[1:4] = 0.0
        self._bias[:] = 0.0
        bg_std = t.gyro_bias_std
        if gyro_bias is not None:
            self._bias_g[:] = gyro_bias.bias
            bg_std = gyro_bias.std
        var = np.concatenate(
            [
                [t.init_tilt_std**2] * 2 + [t.init_yaw_std**2],
                [t.init_vel_std**2] * 3,
                [t.init_pos_std**2] * 9,
                [t.init_tilt_std**2] * (self.nx - 21),
                [bg_std**2] * 3,
                [t.accel_bias_std**2] * 3,
            ]
        )
        self.cov[...] = np.diag(var)  # the prior of the world-frame error, moved to the origin o = pos
        move_origin(self.cov, self._origin)
        self._in_state = [False, False]
        self._points.reset()
        self._outputs()

    def _set_dt(self, dt: float) -> None:
        """Constant parts of the mean step (tick ``dt``) and of Phi and Q (correction period ``dc``)."""
        t, phi, ib = self.tuning, self._phi, self._ib
        dc = self._dc = dt * t.correct_every
        g_hat = (self.gravity @ SKEW).reshape(3, 3)
        phi[3:6, 0:3] = g_hat * dc
        phi[6:9, 0:3] = 0.5 * dc * dc * g_hat
        phi[6:9, 3:6] = np.eye(3) * dc
        q = np.zeros(self.nx)
        q[3:6] = t.accel_density**2
        q[9:15] = t.contact_density**2
        q[15:ib] = t.contact_rot_density**2
        q[ib : ib + 3] = t.gyro_bias_walk**2
        q[ib + 3 : ib + 6] = t.accel_bias_walk**2
        self._qdiag = q * dc
        # s_g^2 dc M M^T = (s_g^2 / dc) (M dc)(M dc)^T: the bordered product adds it
        self._cov_aug[self.nx :, self.nx :] = np.eye(3) * t.gyro_density**2 / dc
        self._mean_step[:] = [[1.0, 0.0, 0.0, 0.0, dt], [dt, 1.0, 0.0, 0.0, 0.5 * dt * dt]]
        self._gravity_step[...] = np.outer([dt, 0.5 * dt * dt], self.gravity)
        self._dt = dt

    # ------------------------------------------------------------------ tick
    def step(self, imu: ImuReading, feet: FootKinematics, contact: np.ndarray, dt: float) -> BaseState:
        """Propagate the mean with the IMU over ``dt`` s; every ``correct_every`` ticks, propagate the
        covariance over those ticks, correct with the stance feet and add touched-down feet."""
        rot, vp, omega, trace = self.advance(imu, feet, contact, dt)
        return new_base_state(rot.copy(), vp[1], vp[0], omega, self._bias_out_g, self._bias_out_a, trace)

    def advance(
        self, imu: ImuReading, feet: FootKinematics, contact: np.ndarray, dt: float
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, float | None]:
        """:meth:`step` without the :class:`BaseState`: (rot (3, 3), [vel; pos] (2, 3), omega (3,),
        cov_trace); ``rot`` is the filter's own array, valid until the next tick (the estimator's path)."""
        if dt != self._dt:
            self._set_dt(dt)
        omega = imu.gyro - self._bias_g
        # mean: [v, p] <- [v + a_w dt, p + v dt + a_w dt^2 / 2] with a_w = R a + g; R <- R Exp(w dt)
        np.dot(self.rot, imu.accel - self._bias_a, out=self._acc_w)
        np.add(self._mean_step.dot(self._vec), self._gravity_step, out=self._vp)
        mujoco.mju_quatIntegrate(self._quat, omega, dt)
        mujoco.mju_quat2Mat(self._rot9, self._quat)
        self.ticks += 1
        if self.ticks[0] % self._every == 0:
            self.correction_tick(feet, contact)
        return self.rot, self._vp + self._offset, omega, self._cov_trace

    def mean_arrays(self, dt: float) -> MeanArrays:
        """The arrays of the mean step, for the compiled tick (:mod:`gaitshift.control.estimation.tick`),
        with the constants of tick ``dt`` s set; the filter keeps using them (every update in place)."""
        if dt != self._dt:
            self._set_dt(dt)
        return MeanArrays(
            self._quat, self._rot9, self._buf, self._bias, self._mean_step, self._gravity_step, self._offset,
            self.ticks, self._every,
        )  # fmt: skip

    @property
    def cov_trace(self) -> float:
        """Trace of the base block (R, v, p) of the covariance, as of the last correction tick."""
        return self._cov_trace

    def place_contacts(self, cop: np.ndarray) -> None:
        """The stance points ``r_i`` (module docstring): ``cop`` (2, 2), x, y in the sole frames, m; a NaN
        row keeps that sole's last point. Applied at the next correction tick."""
        self._points.place(cop)

    def correction_tick(self, feet: FootKinematics, contact: np.ndarray) -> None:
        """Covariance over the correction period, recentring, the stance-foot correction and the feet
        that touched down; then the outputs that only change here (biases, covariance trace)."""
        self._propagate_cov()
        self._recentre()
        feet = self._points.apply(feet, self.rot, self._vec[2:4], self._in_state)
        left, right = bool(contact[0]), bool(contact[1])
        was = self._in_state
        measured = (left and was[0], right and was[1])
        if measured[0] or measured[1]:
            self._correct(feet, self._patterns[measured])
            if self.floor is not None:  # a known flat floor (estimation.floor)
                self._on_floor(feet, measured)
        if (left and not was[0]) or (right and not was[1]):
            self._add_contacts(feet, (left and not was[0], right and not was[1]))
        self._in_state = [left, right]
        self._outputs()

    def _outputs(self) -> None:
        """The biases (read-only copies, returned until the next correction) and the trace of the base
        block of P."""
        self._bias_out_g, self._bias_out_a = self._bias[0:3].copy(), self._bias[3:6].copy()
        self._bias_out_g.flags.writeable = self._bias_out_a.flags.writeable = False
        self._cov_trace = sum(self._cov_diag[0:9].tolist())

    def _propagate_cov(self) -> None:
        """``P <- Phi_aug P_aug Phi_aug^T + diag(Q) dc`` over the correction period ``dc``."""
        dc = self._dc
        np.multiply(self.rot, -dc, out=self._phi_rot)
        self._phi_acc[...] = self._phi_rot
        self._phi_skew[...] = self._vec[0:4].dot(SKEW).reshape(4, 3, 3).dot(self._phi_rot)
        self._phi_noise[...] = self._phi_gyro
        cov = self._phi.dot(self._cov_aug).dot(self._phi_t)
        if self.ticks[0] % (SYMMETRISE_EVERY * self._every) == 0:
            cov += cov.T
            cov *= 0.5
        self.cov[...] = cov
        self._cov_diag += self._qdiag

    def _recentre(self) -> None:
        """Move the origin ``o`` to the IMU position ``c = p``: ``p, d_i <- p - c, d_i - c`` and
        ``P <- T P T^T`` with the ``-c^`` blocks of the module docstring."""
        c = self._vec[1].copy()
        self._origin += c
        self._vec[1:4] -= c
        move_origin(self.cov, c)

    def world_covariance(self) -> np.ndarray:
        """The covariance (nx, nx) of the right-invariant error with positions in the world frame
        (origin at zero): the local one moved back by ``-o``."""
        cov = self.cov.copy()
        move_origin(cov, -self._origin)
        return cov

    def _correct(self, feet: FootKinematics, pat: CorrectionPattern) -> None:
        vec, cov = self._vec, self.cov
        z2 = feet.pos.dot(self.rot.T)  # R y - (d - p), both feet
        z2 -= vec[2:4]
        z2 += vec[1]
        z = z2.reshape(6)[pat.rows]
        if self.flat_feet:  # Log(R R_f Z^T) of the measured feet
            err = np.matmul(np.matmul(self.rot, feet.rot), self._zrot.transpose(0, 2, 1)).reshape(2, 9).tolist()
            z = np.concatenate([z, [c for i in pat.feet for c in log_rot(err[i])]])
        pht = cov.dot(pat.ht)
        s = pat.s
        np.dot(pat.h, pht, out=s)
        if feet.var is not self._noise_of:  # kinematics refresh their variances every few ticks
            self._noise_of = feet.var
            noise = np.concatenate((feet.var, feet.rot_var)) if self.flat_feet else feet.var
            noise = noise + self._floor2[0 : noise.size]
            for p in self._patterns.values():
                p.noise = noise[p.rep]
        pat.s_diag += pat.noise
        _, kt, info = dposv(s, pht.T)  # kt = S^{-1} H P = K^T
        if info != 0:  # S not positive definite: skip this correction
            return
        cov -= pht.dot(kt)
        self._apply(z.dot(kt))

    def _on_floor(self, feet: FootKinematics, measured: tuple[bool, bool]) -> None:
        """Eq. (2) of :mod:`~gaitshift.control.estimation.floor` for the flat stance soles."""
        assert self.floor is not None
        normal_z = self.rot[2].dot(feet.rot[:, :, 2].T)  # e_z^T R R_f e_z per sole
        delta = floor_correction(
            self.cov, self._vec[2:4], float(self._origin[2]), self.floor, self.tuning.floor_std**2, normal_z, measured
        )
        if delta is not None:
            self._apply(delta)

    def _apply(self, delta: np.ndarray) -> None:
        """``X <- Exp(delta[:15]) X``, ``Z_i <- Exp(delta_Zi) Z_i``, ``theta <- theta + delta[ib:]``::

        [v, p, d_L, d_R]^T <- [[v, p, d_L, d_R]^T, rho] @ [Exp(phi)^T; J_l(phi)^T]   (lie.exp_blocks)."""
        x, y, z = delta[0:3].tolist()
        blocks, self._dquat[:] = exp_blocks(x, y, z)
        self._exp_flat[:] = blocks
        self._rho[...] = delta[3:15].reshape(4, 3)
        self._vec[0:4] = self._buf[0:4].dot(self._exp_mat)
        mujoco.mju_mulQuat(self._quat, self._dquat, self._quat)
        mujoco.mju_normalize4(self._quat)
        mujoco.mju_quat2Mat(self._rot9, self._quat)
        if self.flat_feet:
            dz = delta[15:21].tolist()
            for i in (0, 1):
                if self._in_state[i]:
                    self._zdquat[:] = quat_exp(dz[3 * i], dz[3 * i + 1], dz[3 * i + 2])
                    mujoco.mju_mulQuat(self._zquat[i], self._zdquat, self._zquat[i])
                    mujoco.mju_normalize4(self._zquat[i])
                    mujoco.mju_quat2Mat(self._zrot9[i], self._zquat[i])
        self._bias += delta[self._ib : self._ib + 6]

    def _add_contacts(self, feet: FootKinematics, new: tuple[bool, bool]) -> None:
        cov, vec, t = self.cov, self._vec, self.tuning
        for i in (0, 1):
            if not new[i]:
                continue
            j = 9 + 3 * i
            vec[2 + i] = vec[1] + self.rot @ feet.pos[i]
            cov[j : j + 3, :] = cov[6:9, :]
            cov[:, j : j + 3] = cov[:, 6:9]
            cov[j : j + 3, j : j + 3] += np.eye(3) * (feet.var[i] + t.foot_floor**2)
            if self.flat_feet:
                j = 15 + 3 * i
                self._zrot[i] = self.rot @ feet.rot[i]
                mujoco.mju_mat2Quat(self._zquat[i], self._zrot9[i])
                cov[j : j + 3, :] = cov[0:3, :]
                cov[:, j : j + 3] = cov[:, 0:3]
                cov[j : j + 3, j : j + 3] += np.eye(3) * (feet.rot_var[i] + t.foot_rot_floor**2)
