"""The gyro calibration's samples from the hold: the gyro's readings less the rate the legs' joint
angles explain, so that a robot that still rocks on its ankles gives its gyro bias.

``Controller.calibrate`` takes the mean of readings "taken while the robot stood still"
(:mod:`gaitshift.control.estimation.calibration`). After the stand-up the simulated G1 is not still: it
rocks on its ankles, pitch rate +-0.05 rad/s with a period near 2 s, damped over seconds (measured in a 2 s
hold, docs/deploy.md); the mean of a 0.5 s hold's readings is then mostly that motion, and the controller,
sure of a wrong bias, faulted within a second of walking. With both soles flat on the floor the pelvis's
rotation is the legs' joint motion. Relative to a sole, the IMU's orientation is a function of the joint
angles alone, ``R(q) = R_sole(q)^T R_imu(q)`` (forward kinematics with the floating base fixed), and the
IMU's rate in its own frame is ``R^T dR/dt``. Its mean over an interval from ``t_a`` to ``t_b`` is

.. math::

    \\bar w_{kin} = \\log(R(q_a)^T R(q_b)) / (t_b - t_a)                                            (1)

exact for a rotation about a fixed axis (the rocking), with the two soles' rotation vectors averaged.
A calibration sample is the mean of the gyro's readings over the interval less (1): a still reading
(bias plus noise) whether the robot rocks or not. It needs no truth: joint angles from ``LowState_``.

Why angles and not the drivers' joint speeds: on the G1 with ``typical`` noise (14-bit encoders) the
speeds are encoder differences, and (1) written with them, ``R_imu^T (J_imu - J_sole) qd`` per tick,
carries 0.067-0.081 rad/s of noise on the pitch axis (roll and yaw: 0.0055). Such samples average to the
right bias (the differences telescope) but their spread states a prior ten times too loose: 0.0015 rad/s
for a 2 s hold, against 0.00016 for a still robot; and a prior that loose alone (the same mean) made the
soak's first 90 s in one process fall on seeds 0 and 1, which hold with the still robot's
(docs/deploy.md, "The hold's length"). Here the readings are cut into windows of :data:`WINDOW`; each
window's mean pose ``q_w`` at its mean time ``c_w`` gives (1) between consecutive windows' centres, and
the gyro's readings between those centres give the mean: the encoders' noise enters divided by the
window's length, and the samples' spread is the gyro's own.
"""

import mujoco
import numpy as np

from gaitshift.errors import InputError

__all__ = ["WINDOW", "LegRate"]

#: readings per window of the calibration's poses (eq. (1)): 40 ms at 2 ms, well under the rocking's period
WINDOW = 20


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
        self.d.qpos[3] = 1.0  # the base at the origin, identity quaternion

    def relative(self, q: np.ndarray) -> list[np.ndarray]:
        """``R(q) = R_sole^T R_imu`` (3, 3) of each sole at the joint angles ``q`` (n,) rad (motor order)."""
        m, d = self.m, self.d
        d.qpos[self.qadr] = q
        mujoco.mj_kinematics(m, d)
        imu = d.site_xmat[self.site].reshape(3, 3)
        return [d.xmat[body].reshape(3, 3).T @ imu for body in self.feet]

    @staticmethod
    def mean_rate(rel_a: list[np.ndarray], rel_b: list[np.ndarray], span: float) -> np.ndarray:
        """Eq. (1): the IMU's mean rate (3,) rad/s in its own frame while each sole's ``R`` goes from
        ``rel_a`` to ``rel_b`` (:meth:`relative`) in ``span`` s with both soles fixed to the floor."""
        vel, quat, out = np.zeros(3), np.zeros(4), np.zeros(3)
        for r_a, r_b in zip(rel_a, rel_b, strict=True):
            mujoco.mju_mat2Quat(quat, (r_a.T @ r_b).ravel())
            mujoco.mju_quat2Vel(vel, quat, span)
            out += vel / len(rel_a)
        return out

    def samples(self, t: np.ndarray, gyro: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, float]:
        """The calibration's samples (module docstring) of the hold's readings at times ``t`` (N,) s: gyro
        (N, 3) rad/s, joint angles ``q`` (N, n) rad. Returns the samples (K, 3) rad/s, one per pair of
        consecutive windows of :data:`WINDOW` readings (K = N // WINDOW - 1; none below two windows), and
        the mean time between them, s."""
        t, gyro, q = np.asarray(t, float), np.asarray(gyro, float), np.asarray(q, float)
        k = len(t) // WINDOW
        if k < 2:
            return np.zeros((0, 3)), 0.0
        cut = slice(0, k * WINDOW)
        centre = t[cut].reshape(k, WINDOW).mean(axis=1)
        rel = [self.relative(pose) for pose in q[cut].reshape(k, WINDOW, -1).mean(axis=1)]
        out = np.zeros((k - 1, 3))
        for w in range(k - 1):
            between = (t >= centre[w]) & (t < centre[w + 1])
            out[w] = gyro[between].mean(axis=0) - self.mean_rate(rel[w], rel[w + 1], float(centre[w + 1] - centre[w]))
        return out, float(np.mean(np.diff(centre)))
