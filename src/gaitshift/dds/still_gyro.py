"""The gyro calibration's samples during the hold: each gyro reading minus the rate the legs' encoders
explain, so that a robot that still rocks on its ankles gives its gyro bias.

``Controller.calibrate`` takes the mean of readings "taken while the robot stood still"
(:mod:`gaitshift.control.estimation.calibration`). After the stand-up the simulated G1 is not still: it
rocks on its ankles, pitch rate +-0.05 rad/s with a period near 2 s, damped over seconds (measured in a 2 s
hold, docs/deploy.md); the mean of a 0.5 s hold's readings is then mostly that motion, and the controller,
sure of a wrong bias, faulted within a second of walking. With both soles flat on the floor the pelvis's
rotation is the legs' joint motion: the IMU's angular velocity, in the IMU frame, is::

    w_kin = R_imu^T (J_imu - J_foot) qd                                                            (1)

(``J_imu``, ``J_foot``: the rotational Jacobians, base frame, of the IMU site and a sole's body with the
floating base held at the identity and at rest; ``qd`` the joint speeds). :meth:`LegRate.residual` gives
``gyro - w_kin`` (mean of (1) over the two feet): a still reading (bias plus noise) whether the robot
rocks or not. It needs no truth: joint angles and speeds from ``LowState_``.
"""

import mujoco
import numpy as np

from gaitshift.errors import InputError

__all__ = ["LegRate"]


class LegRate:
    """Eq. (1) on a robot model (the controller's).

    Args:
        model: the MuJoCo model (a floating base first: qpos[:7], qvel[:6]). imu_site: the IMU's site.
        feet: the sole bodies (left, right). motors: the joints in the frames' motor order.
    """

    def __init__(self, model: mujoco.MjModel, imu_site: str, feet: tuple[str, ...], motors: tuple[str, ...]) -> None:
        self.m, self.d = model, mujoco.MjData(model)
        self.site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, imu_site)
        if self.site < 0:
            raise InputError("imu_site", imu_site, "a site of the robot model")
        self.feet = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, f) for f in feet]
        self.qadr = np.array([model.joint(n).qposadr[0] for n in motors])
        self.vadr = np.array([model.joint(n).dofadr[0] for n in motors])
        self.d.qpos[3] = 1.0  # the base at the origin, identity quaternion
        self.jac = np.zeros((3, model.nv))

    def rate(self, q: np.ndarray, dq: np.ndarray) -> np.ndarray:
        """Eq. (1): the IMU's angular velocity (3,) rad/s in its own frame explained by the joint angles
        ``q`` (n,) rad and speeds ``dq`` (n,) rad/s (motor order) with both soles fixed to the floor."""
        m, d = self.m, self.d
        d.qpos[self.qadr] = q
        mujoco.mj_kinematics(m, d)
        mujoco.mj_comPos(m, d)
        qd = np.zeros(m.nv)
        qd[self.vadr] = dq
        mujoco.mj_jacSite(m, d, None, self.jac, self.site)
        w_imu = self.jac @ qd
        w_feet = np.zeros(3)
        for body in self.feet:
            mujoco.mj_jacBody(m, d, None, self.jac, body)
            w_feet += self.jac @ qd
        rel = w_imu - w_feet / len(self.feet)
        out: np.ndarray = d.site_xmat[self.site].reshape(3, 3).T @ rel
        return out

    def residual(self, gyro: np.ndarray, q: np.ndarray, dq: np.ndarray) -> np.ndarray:
        """The gyro reading (3,) rad/s minus eq. (1): the bias plus the noise on a robot whose soles are flat."""
        out: np.ndarray = np.asarray(gyro, float) - self.rate(q, dq)
        return out
