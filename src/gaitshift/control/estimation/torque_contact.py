"""Sole forces from the motors' torques: contact sensing for a robot without foot-force sensors.

The equations of motion of the floating-base robot (MuJoCo's convention) are

.. math::

    M(q) \\ddot q + b(q, \\dot q) = S^T \\tau + p(q, \\dot q) + \\sum_i J_i(q)^T f_i                (1)

with ``b`` the Coriolis, centrifugal and gravity forces (``qfrc_bias``), ``p`` the model's passive
forces (joint damping and springs, ``qfrc_passive``), ``S^T tau`` the motor torques
on the actuated dofs and ``f_i`` the wrench (force, moment; world frame) on sole ``i`` about its
centre, ``J_i`` (6, nv) that point's translational and rotational Jacobian. Each sole's Jacobian has
nonzero columns on the base and on its own leg's
joints only, so the rows of (1) of leg ``i``'s joints ``L_i`` give one linear system per leg
(Bledt et al. 2018, Hartley et al. 2018: contact from joint torques):

.. math::

    J_{i,L_i}^T f_i = r_{L_i},\\qquad r = M \\ddot q + b - p - S^T \\tau                      (2)

solved in least squares (six leg joints and six wrench components: exact where the leg is not
singular; a five-joint leg leaves the one wrench direction it cannot feel to the minimum norm).
``q``, ``\\dot q`` are the controller's state (the estimate), ``\\ddot q`` the MEASURED
accelerations and ``tau`` the torques the motor drivers reported (``tau_est``), all at the centre of
a window of ``2 n + 1`` ticks (:class:`AccelerationWindow`: second differences of the estimated
joint angles, the torques averaged), so the force is ``n`` ticks late. The accelerations must be
measured, not the ones the whole-body QP planned: the QP's torques and accelerations satisfy (1)
with the QP's own contact forces, so they would only give back what the controller assumed. The
normal force is ``f_i . n_i`` with ``n_i`` the sole's normal (the sole frame's z axis). Its error
comes from the torque readings, from the joints' dry friction (the model's ``frictionloss``, a
constraint force (1) leaves out: 0.3 N m per G1 leg joint, about 1 N on a sole) and from the errors
of the measured accelerations; the estimator's contact trigger and fusion take it as a force signal
(:mod:`gaitshift.control.estimation.contact_fusion`).
"""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np

from gaitshift.errors import InputError

__all__ = ["TorqueContact"]


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
        self.legs = [leg_dofs(m, s.body) for s in robot.soles]
        if any(len(legs) < 3 for legs in self.legs):
            raise InputError("robot.soles", [len(legs) for legs in self.legs], "legs of at least 3 joints each")
        self.actuated = np.asarray(robot.actuated_dofs)
        self._jac = np.zeros((6, m.nv))
        self._r = np.zeros(m.nv)
        self._ma = np.zeros(m.nv)

    def normal_forces(self, data: Any, tau: np.ndarray, qdd: np.ndarray | None) -> np.ndarray:
        """Normal force (2,) N on each sole from ``data`` (the controller's ``MjData`` after
        ``mj_forward``: ``qfrc_bias`` and the frames), the motor torques ``tau`` (nu,) N m and the
        planned accelerations ``qdd`` (nv,) (None: zero)."""
        m, r = self.model, self._r
        r[:] = data.qfrc_bias
        r -= data.qfrc_passive
        if qdd is not None:
            mujoco.mj_mulM(m, data, self._ma, qdd)
            r += self._ma
        r[self.actuated] -= tau
        out = np.zeros(2)
        for s, dofs in enumerate(self.legs):
            centre, rot = self.robot.sole_frame(data, s)
            jac = self._jac
            mujoco.mj_jac(m, data, jac[:3], jac[3:], centre, self.robot.soles[s].body)
            wrench, *_ = np.linalg.lstsq(jac[:, dofs].T, r[dofs], rcond=None)  # (n_leg, 6) J_leg^T
            out[s] = float(wrench[:3] @ rot[:, 2])
        return out


class AccelerationWindow:
    """The last ``2 n + 1`` ticks of the controller's state and the reported torques, and the
    accelerations at the window's centre ``c`` (n ticks ago)::

        qdd_joints = (q_k - 2 q_c + q_{k-2n}) / (n dt)^2        second difference of the joint angles
        qdd_base   = (v_{c+n} - v_{c-n}) / (2 n dt)              central difference of the base velocity

    with the torques averaged over the ticks ``c - n + 1 .. c + n`` that moved it. Angles, not
    velocities: the estimated joint velocities come from encoder differences and their difference is
    ten times noisier (docs/estimation.md, "Contact without foot force")."""

    def __init__(self, n: int, dt: float) -> None:
        if n < 1:
            raise InputError("torque_window", n, "an integer >= 1 (ticks)")
        self.n, self.dt = int(n), float(dt)
        self.qpos: list[np.ndarray] = []
        self.qvel: list[np.ndarray] = []
        self.tau: list[np.ndarray] = []
        self._data: Any = None

    @property
    def full(self) -> bool:
        return len(self.qpos) == 2 * self.n + 1

    def push(self, qpos: np.ndarray, qvel: np.ndarray, tau: np.ndarray) -> None:
        """Add the newest tick (the oldest beyond the window drops out)."""
        for rows, x in ((self.qpos, qpos), (self.qvel, qvel), (self.tau, tau)):
            rows.append(np.array(x, float))
            if len(rows) > 2 * self.n + 1:
                rows.pop(0)

    def centre_data(self, model: Any) -> Any:
        """An ``MjData`` of ``model`` at the window's centre state (``mj_forward`` done)."""
        if self._data is None:
            self._data = mujoco.MjData(model)
        d = self._data
        d.qpos[:], d.qvel[:] = self.qpos[self.n], self.qvel[self.n]
        mujoco.mj_forward(model, d)
        return d

    def acceleration(self) -> np.ndarray:
        """The accelerations (nv,) at the centre (class docstring)."""
        n, h = self.n, self.n * self.dt
        acc: np.ndarray = (self.qvel[2 * n] - self.qvel[0]) / (2 * h)
        acc[6:] = (self.qpos[2 * n][7:] - 2 * self.qpos[n][7:] + self.qpos[0][7:]) / (h * h)
        return acc

    def mean_torque(self) -> np.ndarray:
        """The reported torques (nu,) averaged over the ticks that moved the centre state."""
        mean: np.ndarray = np.mean(self.tau[1:], axis=0)
        return mean
