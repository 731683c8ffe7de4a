"""Independent helpers of the estimation tests: error of an estimate against the truth (scipy and closed
forms, not the filter's own group code) and a loop that runs a filter over synthetic readings."""

from __future__ import annotations

import numpy as np
from scipy.linalg import expm
from scipy.spatial.transform import Rotation

from gaitshift.control.estimation import FootKinematics, ImuReading


def se23(rot: np.ndarray, vel: np.ndarray, pos: np.ndarray) -> np.ndarray:
    """The 5 x 5 matrix [[R, v, p], [0, I_2]] of SE_2(3)."""
    x = np.eye(5)
    x[0:3, 0:3], x[0:3, 3], x[0:3, 4] = rot, vel, pos
    return x


def hat(xi: np.ndarray) -> np.ndarray:
    """se_2(3) matrix of (xi_R, xi_v, xi_p) (9,)."""
    m = np.zeros((5, 5))
    w = xi[0:3]
    m[0:3, 0:3] = [[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]]
    m[0:3, 3], m[0:3, 4] = xi[3:6], xi[6:9]
    return m


def right_invariant_error(true: np.ndarray, est: np.ndarray) -> np.ndarray:
    """xi (9,) with true = Exp(xi) est on SE_2(3): ``xi_R = Log(R R_hat^T)`` (scipy) and
    ``xi_v, xi_p = J_l(xi_R)^{-1} (v - R R_hat^T v_hat, ...)`` with the closed-form inverse left Jacobian
    ``J_l^{-1} = I - [w]/2 + (1/t^2 - (1 + cos t)/(2 t sin t)) [w]^2`` (Barfoot 2017, eq. 7.87)."""
    eta = true @ np.linalg.inv(est)
    w = Rotation.from_matrix(eta[0:3, 0:3]).as_rotvec()
    t = np.linalg.norm(w)
    k = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    c = 1.0 / 12.0 if t < 1e-6 else 1.0 / t**2 - (1.0 + np.cos(t)) / (2.0 * t * np.sin(t))
    jinv = np.eye(3) - 0.5 * k + c * k @ k
    return np.concatenate([w, jinv @ eta[0:3, 3], jinv @ eta[0:3, 4]])


def perturb(true: np.ndarray, xi: np.ndarray) -> np.ndarray:
    """The estimate est with true = Exp(xi) est (scipy ``expm``)."""
    return np.linalg.inv(expm(hat(xi))) @ true


def angle_between(r1: np.ndarray, r2: np.ndarray) -> float:
    """Rotation angle of r1 r2^T, rad."""
    return float(np.linalg.norm(Rotation.from_matrix(r1 @ r2.T).as_rotvec()))


def run(filt, walk, imu: list[ImuReading], feet: list[FootKinematics], ticks: int | None = None) -> list:
    """Step ``filt`` over the synthetic readings from tick 1; the list of BaseState (tick 1..K-1)."""
    end = walk.t.size if ticks is None else ticks
    return [filt.step(imu[k], feet[k], walk.contact[k], walk.dt) for k in range(1, end)]
