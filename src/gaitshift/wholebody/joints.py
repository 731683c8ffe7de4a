"""Joint trajectories of a robot (q(t), q̇(t) in MuJoCo order), their file, and the helpers around them.

* :class:`JointTrajectory`: ``t`` (N,), ``qpos`` (N, nq), ``qvel`` (N, nv), ``meta``; saved as .npz;
* :func:`qpos_difference` (q1 ⊖ q0 on the configuration manifold) and :func:`joint_velocities`
  (central differences of q, second order in dt);
* :func:`subsample` (every k-th plan sample) and :func:`load_plan` (a plan from a file or a scenario).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.common.atomic import atomic_path
from gaitshift.common.jsonsafe import finite_json
from gaitshift.errors import InputError
from gaitshift.trajectory.contract import Trajectory
from gaitshift.trajectory.formats import NPZ_ERRORS


@dataclass(frozen=True)
class JointTrajectory:
    """Joint trajectories of a robot.

    Attributes:
        t: (N,) time, s.
        qpos: (N, nq) MuJoCo generalized positions (free joint: x, y, z, qw, qx, qy, qz first).
        qvel: (N, nv) MuJoCo generalized velocities (free joint: world linear, body angular first).
        meta: JSON-able dict: robot, mjcf, joint_names, qpos_names, qvel_names, ik errors, source.
    """

    t: np.ndarray
    qpos: np.ndarray
    qvel: np.ndarray
    meta: dict[str, Any] = field(default_factory=dict)

    def save(self, path: str | Path) -> Path:
        """Write ``t``, ``qpos``, ``qvel`` and ``meta`` (JSON string) to an ``.npz``, atomically."""
        path = Path(path)
        if path.suffix.lower() != ".npz":
            raise InputError("out", str(path), "a file ending in .npz")
        with atomic_path(path) as tmp:
            np.savez_compressed(
                tmp,
                t=self.t,
                qpos=self.qpos,
                qvel=self.qvel,
                meta=np.array(json.dumps(finite_json(self.meta), allow_nan=False)),
            )
        return path

    @classmethod
    def load(cls, path: str | Path) -> JointTrajectory:
        path = Path(path)
        if not path.is_file():
            raise InputError("file", str(path), "an existing joints .npz file")
        allowed = "a joints .npz file from `gaitshift wholebody` (t, qpos, qvel, meta)"
        try:
            with np.load(path, allow_pickle=False) as z:
                missing = [k for k in ("t", "qpos", "qvel", "meta") if k not in z.files]
                if missing:
                    raise InputError("file", str(path), f"{allowed}; missing {missing}")
                t, qpos, qvel, meta = z["t"], z["qpos"], z["qvel"], json.loads(str(z["meta"]))
        except (*NPZ_ERRORS, json.JSONDecodeError) as exc:
            if isinstance(exc, InputError):
                raise
            raise InputError("file", str(path), f"{allowed} (unreadable: {str(exc).splitlines()[0][:80]})") from None
        if not isinstance(meta, dict):
            raise InputError("file", str(path), f"{allowed} (meta is not a JSON object)")
        return cls(t, qpos, qvel, meta)


def subsample(traj: Trajectory, rate: float | None) -> Trajectory:
    """Every k-th sample of ``traj`` so that the step is 1/``rate`` (k integer), or ``traj`` itself."""
    if rate is None or len(traj) < 2:
        return traj
    if not (rate > 0 and math.isfinite(rate)):
        raise InputError("rate", rate, "a positive sampling rate, Hz")
    k = 1.0 / (rate * traj.dt)
    step = round(k)
    if step < 1 or abs(k - step) > 1e-6 * k:
        raise InputError("rate", rate, f"1/(k dt) for an integer k >= 1 (plan step dt = {traj.dt:g} s)")
    if step == 1:
        return traj
    arrays = {key: v[::step] if np.ndim(v) and len(v) == len(traj) else v for key, v in traj.arrays().items()}
    arrays["footsteps"], arrays["footstep_side"] = traj.footsteps, traj.footstep_side
    return Trajectory.from_arrays(arrays, dict(traj.meta))


# ====================================================================== manifold helpers
def _quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    aw, ax, ay, az = np.moveaxis(a, -1, 0)
    bw, bx, by, bz = np.moveaxis(b, -1, 0)
    return np.stack(
        [
            aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
        ],
        axis=-1,
    )


def _quat_log(q: np.ndarray) -> np.ndarray:
    """Rotation vector (..., 3) of unit quaternions (..., 4) (w first), shortest path."""
    q = np.where(q[..., :1] < 0, -q, q)
    v = q[..., 1:]
    s = np.linalg.norm(v, axis=-1)
    angle = 2.0 * np.arctan2(s, q[..., 0])
    scale = np.where(s > 1e-12, angle / np.maximum(s, 1e-300), 2.0)
    return v * scale[..., None]


def qpos_difference(model: Any, q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """q1 ⊖ q0 for arrays of configurations (..., nq) -> (..., nv), like ``mj_differentiatePos``
    with dt = 1: free-joint linear part in the world frame, angular part in the body frame
    (log of conj(quat0) * quat1); hinges and slides subtract."""
    out = np.empty((*q0.shape[:-1], model.nv))
    out[..., 0:3] = q1[..., 0:3] - q0[..., 0:3]
    conj = q0[..., 3:7] * np.array([1.0, -1.0, -1.0, -1.0])
    out[..., 3:6] = _quat_log(_quat_mul(conj, q1[..., 3:7]))
    out[..., 6:] = q1[..., 7:] - q0[..., 7:]
    return out


def joint_velocities(model: Any, qpos: np.ndarray, dt: float) -> np.ndarray:
    """q̇ (N, nv) from q (N, nq): central differences inside, one-sided at both ends."""
    n = len(qpos)
    qvel = np.zeros((n, model.nv))
    if n < 2:
        return qvel
    qvel[1:-1] = qpos_difference(model, qpos[:-2], qpos[2:]) / (2 * dt)
    qvel[0] = qpos_difference(model, qpos[0], qpos[1]) / dt
    qvel[-1] = qpos_difference(model, qpos[-2], qpos[-1]) / dt
    return qvel


def coordinate_names(model: Any) -> tuple[list[str], list[str]]:
    """Names of the qpos (nq) and qvel (nv) entries of ``model``, as stored in a joints file's meta:
    the joint name, and for the free joint (``root`` if unnamed) ``<name>:x, y, z, qw, qx, qy, qz`` and
    ``<name>:vx, vy, vz, wx, wy, wz``."""
    import mujoco

    qpos_names: list[str] = []
    qvel_names: list[str] = []
    for j in range(model.njnt):
        name = model.joint(j).name or "root"
        if int(model.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_FREE):
            qpos_names += [f"{name}:{c}" for c in ("x", "y", "z", "qw", "qx", "qy", "qz")]
            qvel_names += [f"{name}:{c}" for c in ("vx", "vy", "vz", "wx", "wy", "wz")]
        else:
            qpos_names.append(name)
            qvel_names.append(name)
    return qpos_names, qvel_names


def load_plan(source: Trajectory | str | Path) -> Trajectory:
    """A plan from a trajectory file (.npz/.csv/.json), or planned from a scenario (built-in name or
    .yaml path)."""
    if isinstance(source, Trajectory):
        return source
    path = Path(str(source))
    if path.suffix.lower() in (".npz", ".csv", ".json"):
        return Trajectory.load(path)
    from gaitshift.api import plan
    from gaitshift.scenario import load_scenario

    return plan(load_scenario(str(source)))
