"""The motion to export: MuJoCo configurations of one robot over time, from a plan or a simulation log.

* a plan (``gaitshift plan ... --out plan.npz``, the trajectory contract): the whole-body IK
  (:mod:`gaitshift.wholebody.ik`) with its reference settings (``REFERENCE_SETTINGS``: every joint
  within its soft range, the pelvis upright, the swing soles' pitch soft) solves q(t) at a rate of
  1/(k dt) >= max(200 Hz, 4 fps) (k integer) (its q̇: central differences on the configuration
  manifold); the kinematic motion;
* a simulation log (``gaitshift simulate ... --out sim.npz``, :class:`gaitshift.sim.result.SimResult`):
  the logged ``qpos`` and ``qvel`` of every control tick, the motion the robot actually made (up to
  the fall, if it fell).

The export resamples ``qpos`` and differentiates the frames (:mod:`gaitshift.export.resample`); the
source's ``qvel`` is kept for comparison.

The robot is ``--robot``, else the one the file names (a log's ``meta.robot``, a plan's
``meta.scenario.robot``); a log is tied to its robot, so another ``--robot`` is an error.
"""

from __future__ import annotations

import json
import math
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.errors import InputError
from gaitshift.robots.config import RobotConfig, load_robot

#: what the input file may be
ALLOWED = "a plan .npz (gaitshift plan --out X.npz) or a simulation log .npz (gaitshift simulate --out X.npz)"
#: keys that make an .npz a simulation log
LOG_KEYS = ("t", "qpos", "qvel", "meta", "fell")
#: lowest rate of the whole-body IK of a plan, Hz (and at least 4 output frames per IK sample)
MIN_IK_RATE = 200.0


@dataclass(frozen=True)
class SourceMotion:
    """Configurations of ``robot`` at times ``t`` (N,): ``qpos`` (N, nq), ``qvel`` (N, nv).
    ``kind``: ``plan`` or ``simulation``; ``meta``: what the file says about it."""

    kind: str
    robot: RobotConfig
    t: np.ndarray
    qpos: np.ndarray
    qvel: np.ndarray
    meta: dict[str, Any] = field(default_factory=dict)


def load_source(path: str | Path, robot: str | None, fps: float) -> SourceMotion:
    """Read ``path`` (see module docstring); a plan is solved by the IK at a rate suited to ``fps``.

    Raises:
        InputError: not an existing .npz, neither a plan nor a log, no robot known, a --robot that
            is not the log's robot, or a log whose qpos does not fit the robot's model.
        InfeasibleError: the robot cannot follow the plan (whole-body IK).
    """
    path = Path(path)
    if path.suffix.lower() != ".npz" or not path.is_file():
        raise InputError("input", str(path), ALLOWED)
    try:
        with np.load(path, allow_pickle=False) as z:
            files = set(z.files)
            log = {k: z[k] for k in LOG_KEYS} if set(LOG_KEYS) <= files else None
    except (OSError, ValueError, zipfile.BadZipFile, EOFError):
        raise InputError("input", str(path), ALLOWED + "; this is not a readable .npz") from None
    if log is not None:
        return _from_log(path, log, robot)
    if "com_pos" in files and "foot_pos" in files:
        return _from_plan(path, robot, fps)
    raise InputError("input", str(path), ALLOWED + f"; found keys {sorted(files)[:8]}")


def _from_log(path: Path, log: dict[str, np.ndarray], robot: str | None) -> SourceMotion:
    try:
        meta = json.loads(str(log["meta"]))
    except json.JSONDecodeError as exc:
        raise InputError("input", str(path), f"a simulation log whose meta is JSON ({exc.msg})") from None
    if not isinstance(meta, dict):
        raise InputError("input", str(path), "a simulation log whose meta is a JSON object")
    own = meta.get("robot", "g1")
    if robot is not None and load_robot(robot) != load_robot(own):
        raise InputError("--robot", robot, f"the robot the log was simulated with ({own}), or no --robot")
    cfg = load_robot(own)
    model = cfg.model()
    t, qpos, qvel = (np.asarray(log[k], float) for k in ("t", "qpos", "qvel"))
    if qpos.ndim != 2 or qpos.shape[1] != model.nq or qvel.shape != (len(t), model.nv) or len(t) < 2:
        raise InputError("input", str(path), f"a log of {cfg.name} (qpos width {model.nq}, at least 2 ticks)")
    if not (np.all(np.isfinite(qpos)) and np.all(np.isfinite(qvel)) and np.all(np.diff(t) > 0)):
        raise InputError("input", str(path), "a log with finite qpos, qvel and increasing t")
    return SourceMotion("simulation", cfg, t, qpos, qvel, {"robot": cfg.name, "fell": bool(log["fell"])})


def _from_plan(path: Path, robot: str | None, fps: float) -> SourceMotion:
    from gaitshift.api import named_robot
    from gaitshift.trajectory.contract import Trajectory
    from gaitshift.wholebody.ik import REFERENCE_SETTINGS, WholeBodyIK

    traj = Trajectory.load(path)
    named = named_robot(traj.meta)
    if robot is None and named is None:
        raise InputError("--robot", None, "a built-in robot name or robot YAML (the plan names none)")
    cfg = load_robot(robot if robot is not None else str(named))
    step = max(1, math.floor(1.0 / (traj.dt * max(MIN_IK_RATE, 4.0 * fps)) + 1e-9))
    joints = WholeBodyIK(cfg, REFERENCE_SETTINGS).solve(traj, rate=1.0 / (step * traj.dt))
    meta = {"robot": cfg.name, "ik_rate_hz": 1.0 / (step * traj.dt), "ik": joints.meta["ik"]}
    return SourceMotion("plan", cfg, joints.t, joints.qpos, joints.qvel, meta)
