"""Sole forces from the motors' torques: contact sensing for a robot without foot-force sensors.

The equations of motion of the floating-base robot (MuJoCo's convention) are

.. math::

    M(q) \\ddot q + b(q, \\dot q) = S^T \\tau + p(q, \\dot q) + \\sum_i J_i(q)^T f_i                (1)

with ``b`` the Coriolis, centrifugal and gravity forces (``qfrc_bias``), ``p`` the model's passive
forces (joint damping and springs, ``qfrc_passive``), ``S^T tau`` the motor torques
on the actuated dofs and ``f_i`` the wrench (force, moment; world frame) on sole ``i`` about its
centre, ``J_i`` (6, nv) that point's translational and rotational Jacobian. Each sole's Jacobian has
nonzero columns on the base and on the joints of its chain to the base only, so the rows of (1) of leg
``i``'s joints ``L_i`` give one linear system per leg (Bledt et al. 2018, Hartley et al. 2018: contact
from joint torques). ``L_i`` is the chain without the joints on both chains (the T1's waist, between its
base and its hips): their rows carry both soles' wrenches, and a leg's system that kept them would put
the other sole's share on its own (on the T1 at rest: 0.011 N of 110 N, the centre of pressure 0.4 mm off):

.. math::

    J_{i,L_i}^T f_i = r_{L_i},\\qquad r = M \\ddot q + b - p - S^T \\tau                      (2)

solved exactly where both legs have six joints and six wrench components (one batched solve; in least
squares where a leg is exactly singular), else in least squares (a five-joint leg leaves the one wrench
direction it cannot feel to the minimum norm).
``q``, ``\\dot q`` are the controller's state (the estimate), ``\\ddot q`` the MEASURED
accelerations and ``tau`` the torques the motor drivers reported (``tau_est``), all at the centre of
a window of ``2 n + 1`` ticks (:class:`AccelerationWindow`: second differences of the estimated
joint angles, the torques under the same triangular weights), so the force is ``n`` ticks late.
The accelerations must be
measured, not the ones the whole-body QP planned: the QP's torques and accelerations satisfy (1)
with the QP's own contact forces, so they would only give back what the controller assumed. The
normal force is ``f_i . n_i`` with ``n_i`` the sole's normal (the sole frame's z axis). Its error
comes from the torque readings, from the joints' dry friction (the model's ``frictionloss``, a
constraint force (1) leaves out: 0.3 N m per G1 leg joint, about 1 N on a sole) and from the errors
of the measured accelerations; the estimator's contact trigger and fusion take it as a force signal
(:mod:`gaitshift.control.estimation.contact_fusion`).

The same wrench gives each sole's centre of pressure. With ``f``, ``m`` the force and the moment about the
sole's centre in the sole frame (``R_s^T f_i``), the point of the sole plane about which the moment has no
horizontal part is

.. math::

    r = \\left(\\operatorname{clip}(-m_y / f_z, \\pm L/2),\\ \\operatorname{clip}(m_x / f_z, \\pm W/2)\\right)   (4)

(``L`` x ``W`` the sole size), given where the sole carries at least :data:`COP_MIN_LOAD` of the robot's
weight (a lighter load's moment is mostly the foot's own dynamics and the torque readings' error). The
estimator takes it as the stance point of the sole (:mod:`~gaitshift.control.estimation.inekf`).

The encoders' noise reaches the force through the accelerations. The joint filter's angle (per joint,
``x_{k+1} = A x_k + K z_k``, ``x = [q, qd]``, readings of covariance ``R_z``) is stationary with the
covariance ``S = A S A^T + K R_z K^T`` and the autocovariance ``R(m) = (A^m S)_qq``, so the window's
second difference has

.. math::

    \\operatorname{Var} \\ddot q = \\frac{6 R(0) - 8 R(n) + 2 R(2 n)}{(n\\, dt)^4}                     (3)

(:func:`second_difference_variance`), and (2) is linear in ``\\ddot q``: the normal force's noise is
``sigma_f^2 = sum_j (d f / d qdd_j)^2 Var qdd_j`` (:meth:`TorqueContact.acceleration_gains`, at the standing
pose).
On the G1 (n = 5) that is 0.009 of the weight for ``typical`` noise (14-bit encoders) and 0.198 for
``rl-peer`` noise (+-0.01 rad per reading); the error measured on g1-walk against the true force, 0.027 and
0.202 (docs/estimation.md, "Heavy sensor noise"). The moments take their noise the same way, and eq. (4)
divides it by the load: at half the G1's weight, a CoP std along the sole of 1.4 mm for ``typical`` noise
(n = 5) and about 1 cm for ``rl-peer`` (the window it gets, n = 10); the controller takes the CoP as the stance
point only where that std is small (:data:`gaitshift.control.state.COP_STD_MAX`).
"""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np
from scipy.linalg import solve_discrete_lyapunov

from gaitshift.errors import InputError
from gaitshift.robots.model import forward_terms

__all__ = ["COP_MIN_LOAD", "AccelerationWindow", "TorqueContact", "second_difference_variance"]

#: share of the robot's weight a sole must carry for its centre of pressure (eq. (4)) to be given
COP_MIN_LOAD = 0.15


def second_difference_variance(transition: np.ndarray, gain: np.ndarray, reading_cov: np.ndarray, n: int) -> float:
    """``(n dt)^4 Var qdd`` of eq. (3), rad^2: the variance of ``q_{c+n} - 2 q_c + q_{c-n}`` of one
    joint's filtered angle, from the joint filter's transition ``A`` (2, 2) and gain ``K`` (2, 2) and the
    readings' covariance ``R_z`` (2, 2)."""
    a = np.asarray(transition, float)
    cov = solve_discrete_lyapunov(a, gain @ reading_cov @ gain.T)

    def auto(m: int) -> float:
        return float((np.linalg.matrix_power(a, m) @ cov)[0, 0])

    return max(0.0, 6.0 * auto(0) - 8.0 * auto(n) + 2.0 * auto(2 * n))


def leg_dofs(model: Any, body: int) -> np.ndarray:
    """The hinge and slide dofs on the chain from ``body`` up to (not including) the floating base."""
    dofs: list[int] = []
    b = body
    while b > 0:
        for j in range(model.body_jntadr[b], model.body_jntadr[b] + model.body_jntnum[b]):
            if int(model.jnt_type[j]) in (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)):
                dofs.append(int(model.jnt_dofadr[j]))
        b = int(model.body_parentid[b])
    return np.array(sorted(dofs), dtype=int)


class TorqueContact:
    """Eq. (2) of the module docstring for the two soles.

    Args:
        robot: the controller's robot model (:class:`gaitshift.robots.model.RobotModel`).
    """

    def __init__(self, robot: Any) -> None:
        m = robot.model
        self.robot, self.model = robot, m
        chains = [leg_dofs(m, s.body) for s in robot.soles]
        shared = np.intersect1d(chains[0], chains[1])  # on both chains (the T1's waist): both soles' wrenches load them
        self.legs = [np.setdiff1d(chain, shared) for chain in chains]
        if any(len(legs) < 3 for legs in self.legs):
            raise InputError("robot.soles", [len(legs) for legs in self.legs], "legs of at least 3 joints each")
        self.actuated = np.asarray(robot.actuated_dofs)
        self.half_sole = 0.5 * np.asarray(robot.robot.sole_size, float)  # (L/2, W/2), m
        self.min_load = COP_MIN_LOAD * robot.weight  # N
        #: each leg has six joints: eq. (2) is square, one batched solve (:meth:`_solve`)
        self.square = all(len(legs) == 6 for legs in self.legs)
        self._jac = np.zeros((2, 6, m.nv))
        self._r = np.zeros(m.nv)
        self._ma = np.zeros(m.nv)

    def normal_forces(self, data: Any, tau: np.ndarray, qdd: np.ndarray | None) -> np.ndarray:
        """Normal force (2,) N on each sole from ``data`` (the controller's ``MjData`` after
        ``mj_forward``: ``qfrc_bias`` and the frames), the motor torques ``tau`` (nu,) N m and the
        planned accelerations ``qdd`` (nv,) (None: zero)."""
        return self.sole_wrenches(data, tau, qdd)[:, 2]

    def sole_loads(self, data: Any, tau: np.ndarray, qdd: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`normal_forces` (2,) N and each sole's centre of pressure (2, 2), x, y in the sole frame, m
        (eq. (4); a NaN row where the sole carries less than :data:`COP_MIN_LOAD` of the weight)."""
        w = self.sole_wrenches(data, tau, qdd)
        cop = np.full((2, 2), np.nan)
        for s in (0, 1):
            fz, mx, my = w[s, 2:5].tolist()
            if fz >= self.min_load:  # eq. (4)
                cop[s] = np.clip((-my / fz, mx / fz), -self.half_sole, self.half_sole)
        return w[:, 2].copy(), cop

    def sole_wrenches(self, data: Any, tau: np.ndarray, qdd: np.ndarray | None) -> np.ndarray:
        """Eq. (2) for both soles: the wrench (2, 6) [force N; moment N m about the centre] on each sole,
        in its sole frame (arguments as :meth:`normal_forces`)."""
        m, r, jac = self.model, self._r, self._jac
        r[:] = data.qfrc_bias
        r -= data.qfrc_passive
        if qdd is not None:
            mujoco.mj_mulM(m, data, self._ma, qdd)
            r += self._ma
        r[self.actuated] -= tau
        rot = np.empty((2, 3, 3))
        for s, sole in enumerate(self.robot.soles):
            centre, rot[s] = self.robot.sole_frame(data, s)
            mujoco.mj_jac(m, data, jac[s, :3], jac[s, 3:], centre, sole.body)
        world = self._solve(jac, r).reshape(2, 2, 3)  # per sole: force, moment in the world frame
        out: np.ndarray = np.einsum("ski,sij->skj", world, rot).reshape(2, 6)  # in the sole frame
        return out

    def _solve(self, jac: np.ndarray, r: np.ndarray) -> np.ndarray:
        """``J_{i,L_i}^T f_i = r_{L_i}`` of eq. (2) for both legs (jac (2, 6, nv), r (nv,)): one batched
        solve where each leg has six joints, else each leg's least squares (minimum norm)."""
        legs = self.legs
        if self.square:
            a = np.stack([jac[s][:, dofs].T for s, dofs in enumerate(legs)])  # (2, 6, 6)
            b = np.stack([r[dofs] for dofs in legs])[..., None]
            try:
                solved: np.ndarray = np.linalg.solve(a, b)[..., 0]
                return solved
            except np.linalg.LinAlgError:  # a leg exactly singular: least squares below
                pass
        return np.stack([np.linalg.lstsq(jac[s][:, dofs].T, r[dofs], rcond=None)[0] for s, dofs in enumerate(legs)])

    def acceleration_gains(self, data: Any) -> np.ndarray:
        """``d w / d qdd_j`` (2, 6, nv - 6), per rad/s^2: how each sole's wrench (eq. (2), sole frame; the
        normal force is row 2, the moments rows 3-5) moves with each joint's measured acceleration, at
        the state of ``data`` (after ``mj_forward``); eq. (3) takes the noise from them, ``sigma^2 =
        sum_j (d w / d qdd_j)^2 Var qdd_j``."""
        m = self.model
        zero_tau = np.zeros(m.nu)
        base = self.sole_wrenches(data, zero_tau, None)
        unit, out = np.zeros(m.nv), np.zeros((2, 6, m.nv - 6))
        for j in range(6, m.nv):
            unit[j] = 1.0
            out[:, :, j - 6] = self.sole_wrenches(data, zero_tau, unit) - base
            unit[j] = 0.0
        return out


class AccelerationWindow:
    """The last ``2 n + 1`` ticks of the controller's state and the reported torques, and the
    accelerations and torques at the window's centre ``c`` (n ticks ago), both the same weighted mean
    over the ticks, so that eq. (1) holds for the means as it holds at each tick.

    With the integrator's update ``v_{k+1} = v_k + dt a_k``, ``q_{k+1} = q_k + dt v_{k+1}``, the second
    difference of the joint angles is a triangular mean of the accelerations::

        (q_{c+n} - 2 q_c + q_{c-n}) / (n dt)^2 = sum_j w_j a_{c+j},   w_j = (n - |j|) / n^2,  |j| < n

    (the weights sum to 1). The base's accelerations take the same mean from its velocities,
    ``(mean(v_{c+1..c+n}) - mean(v_{c-n+1..c})) / (n dt)``, and the torques too. Each tick of the
    window pairs a state with the torque that moved it on (:meth:`push`), so ``a_{c+j}`` goes with
    the torque of tick ``c + j``. A uniform mean of the torques against the triangular one of the accelerations
    would read a torque step inside the window as a sole force (at every planned touch-down and
    lift-off, where the controller switches its torques). Angles, not velocities, for the joints: the
    estimated joint velocities come from encoder differences and their difference is ten times
    noisier (docs/estimation.md, "Contact without foot force")."""

    def __init__(self, n: int, dt: float) -> None:
        if n < 1:
            raise InputError("torque_window", n, "an integer >= 1 (ticks)")
        self.n, self.dt = int(n), float(dt)
        self.rows = 2 * self.n + 1
        #: the window's states and torques, oldest first (row j <-> tick c - n + j); allocated at the first push
        self.qpos, self.qvel, self.tau = np.zeros((0, 0)), np.zeros((0, 0)), np.zeros((0, 0))
        self.count = 0
        self._data: Any = None
        idx = np.arange(self.rows)
        #: weight of the torque of each tick of the window (tick c + j <-> w_j; class docstring)
        self.weights = np.maximum(self.n - np.abs(idx - self.n), 0) / self.n**2
        h = self.n * self.dt
        #: the base's acceleration as weights on the window's velocities (class docstring)
        self.base_weights = np.where(idx > self.n, 1.0, np.where(idx >= 1, -1.0, 0.0)) / (self.n * h)

    @property
    def full(self) -> bool:
        return self.count >= self.rows

    def push(self, qpos: np.ndarray, qvel: np.ndarray, tau: np.ndarray) -> None:
        """Add the newest tick: a state (qpos (nq,), qvel (nv,)) and the torques (nu,) N m that moved it on
        (the motors' report of the next frame: the controller pushes its previous tick's state with the
        new frame's ``tau_est``). The oldest tick beyond the window drops out."""
        if self.count == 0:
            self.qpos, self.qvel, self.tau = (np.zeros((self.rows, len(x))) for x in (qpos, qvel, tau))
        for rows, x in ((self.qpos, qpos), (self.qvel, qvel), (self.tau, tau)):
            rows[:-1] = rows[1:]
            rows[-1] = x
        self.count += 1

    def centre_data(self, model: Any) -> Any:
        """An ``MjData`` of ``model`` at the window's centre state (:func:`~gaitshift.robots.model.forward_terms`
        done: the frames, the mass matrix, ``qfrc_bias`` and ``qfrc_passive`` that eq. (2) reads)."""
        if self._data is None:
            self._data = mujoco.MjData(model)
        d = self._data
        d.qpos[:], d.qvel[:] = self.qpos[self.n], self.qvel[self.n]
        forward_terms(model, d)
        return d

    def acceleration(self) -> np.ndarray:
        """The triangular mean (nv,) of the accelerations about the centre (class docstring)."""
        n, h, q = self.n, self.n * self.dt, self.qpos
        acc: np.ndarray = self.base_weights @ self.qvel
        acc[6:] = (q[2 * n, 7:] - 2 * q[n, 7:] + q[0, 7:]) / (h * h)
        return acc

    def mean_torque(self) -> np.ndarray:
        """The reported torques (nu,) under the accelerations' weights (class docstring)."""
        mean: np.ndarray = self.weights @ self.tau
        return mean
