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
``q``, ``\\dot q`` are the controller's state (the estimate), ``\\ddot q`` the MEASURED accelerations
(the controller differentiates its estimated velocities: :meth:`gaitshift.control.state.ControllerState`
runs eq. (2) one tick back) and ``tau`` the torques the motor drivers reported over that interval
(``tau_est``). The accelerations must be measured, not the ones the whole-body QP planned: the QP's
torques and accelerations satisfy (1) with the QP's own contact forces, so they would only give back
what the controller assumed. The normal force is ``f_i . n_i`` with ``n_i`` the sole's normal (the
sole frame's z axis). Its error comes from the torque readings, from the joints' dry friction (the
model's ``frictionloss``, a constraint force (1) leaves out: 0.3 N m per G1 leg joint, about 1 N on a
sole) and from the errors of the measured accelerations; the estimator's contact trigger and fusion
take it as a force signal (:mod:`gaitshift.control.estimation.contact_fusion`).
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
