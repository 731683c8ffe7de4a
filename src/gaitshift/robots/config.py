"""Robot configurations: which MJCF, which frames are the soles, which joints are legs, the standing pose.

A robot is described by a small YAML file (package data ``gaitshift/robots/configs/<name>.yaml`` or any
path; its keys: :mod:`gaitshift.robots.schema`). Everything that the model already knows is read from
the model, never copied into the YAML:

* joint ranges (``jnt_range``) and torque limits (:func:`gaitshift.robots.mjcf.torque_limit`);
* the floating base (the body of the model's one free joint);
* the soles' contact points, and by default their centre, size and frame (:mod:`gaitshift.robots.soles`);
* the nominal CoM height: height of the whole-body CoM above the sole plane in the standing pose
  (given, or computed by IK for ``com_height``: :mod:`gaitshift.robots.standing`);
* the leg length: distance from the hip-pitch joint axis to the sole centre with every leg joint at 0
  (leg straight), the longest reach of a leg;
* the foot separation: lateral distance between the two sole centres in the standing pose (these three:
  :mod:`gaitshift.robots.dimensions`);
* whether each leg can roll its foot (rank of the leg's angular Jacobian: 5-DOF legs such as the H1's
  cannot).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from pydantic import ValidationError

from gaitshift.errors import InputError
from gaitshift.robots import mjcf as _mj
from gaitshift.robots.dimensions import com_height, foot_roll, foot_separation, leg_length
from gaitshift.robots.schema import RobotYaml
from gaitshift.robots.sensors import RobotSensors, robot_sensors
from gaitshift.robots.soles import SoleGeometry, common_size, sole_geometry
from gaitshift.robots.standing import computed_standing_pose
from gaitshift.scenario.facts import RobotFacts
from gaitshift.scenario.fields import input_error
from gaitshift.scenario.loader import yaml_mapping, yaml_text

#: default CoM height of a computed standing pose, as a fraction of the CoM height with straight legs
STANDING_HEIGHT_FRACTION = 0.92


@dataclass(frozen=True)
class RobotConfig:
    """A humanoid model ready for whole-body IK and simulation (see module docstring).

    Attributes:
        name: short name.
        mjcf: absolute path of the MJCF file.
        sole_bodies: (left, right) body names carrying the soles.
        sole_offsets: (left, right) sole centre in its body frame, m, each (3,).
        sole_quats: (left, right) sole frame in its body frame, quaternion (w, x, y, z).
        soles: (left, right) :class:`~gaitshift.robots.soles.SoleGeometry` (contact geoms and points).
        sole_size: (length, width) of the sole, m.
        torso: body kept upright; base: the body of the free joint.
        hips, knees: (left, right) joint names.
        leg_joints, arm_joints: joint names.
        foot_roll: (left, right) the leg can roll its foot about the sole's x axis.
        standing_pose: ((joint, angle), ...) rad (given or computed).
        joint_names: every hinge/slide joint of the model in qpos order (free joint excluded).
        joint_range: (J, 2) lower/upper limit of each joint of ``joint_names``, rad; +-inf if unlimited.
        soft_joint_fraction: the soft range of a joint is the middle fraction of ``joint_range`` (YAML
            ``limits``; :func:`gaitshift.wholebody.ik_tasks.soft_range`).
        torque_limit: (J,) largest joint torque, N m; inf if the model gives none.
        velocity_limit: (J,) largest joint speed, rad/s, from the YAML's ``velocity_limits`` (the maker's
            limits: the IK and ``simulate`` refuse plans above them); inf where the YAML gives none.
        damping_speed: (J,) torque limit / joint damping of the model, rad/s (inf without damping): above
            it the motor alone cannot drive the joint (:func:`gaitshift.robots.mjcf.damping_speed_limit`;
            ``gaitshift robot check`` reports plans that need more).
        mass: total mass, kg.
        com_height: nominal CoM height above the sole plane in the standing pose, m.
        leg_length: hip-pitch axis to sole centre, leg straight, m.
        foot_separation: lateral distance of the two soles in the standing pose, m.
        sensors: the IMU frame and whether the soles measure force (:mod:`gaitshift.robots.sensors`).
        control: ((gain name, value), ...) controller gains of this robot.
        ik: ((IKSettings field, value), ...) the robot's whole-body IK weights (YAML ``ik``).
        flight_scale: factor on the flight time of running steps of scaled scenarios (YAML ``gait``).
        step_width: lateral step width of scaled scenarios, m; None: ``foot_separation`` (YAML ``gait``).
        run_contact_length: the longest running stance travel, m (:mod:`gaitshift.gait.run_timing`);
            inf if the YAML's ``gait`` gives none (the nominal running timing at every speed).
        step_time_scale: factor on the support times and strides of scaled scenarios (YAML ``gait``).
        max_stride: cap on the stride of scaled scenarios, m; None: lambda x the scenario's (``gait``).
        swing_height: swing-foot clearance of scaled scenarios, m; None: lambda x the scenario's (``gait``).
        max_yaw_rate: cap on the turn rate of scaled live-command scenarios, rad/s; None: none (``gait``).
        source: the built-in name or YAML path it was loaded from.
    """

    name: str
    description: str
    mjcf: Path
    sole_bodies: tuple[str, str]
    sole_offsets: tuple[tuple[float, float, float], tuple[float, float, float]]
    sole_quats: tuple[tuple[float, ...], tuple[float, ...]]
    soles: tuple[SoleGeometry, SoleGeometry]
    sole_size: tuple[float, float]
    torso: str
    base: str
    hips: tuple[str, str]
    knees: tuple[str, str]
    leg_joints: tuple[str, ...]
    arm_joints: tuple[str, ...]
    foot_roll: tuple[bool, bool]
    standing_pose: tuple[tuple[str, float], ...]
    velocity_limits_source: str
    joint_names: tuple[str, ...]
    joint_range: np.ndarray
    torque_limit: np.ndarray
    velocity_limit: np.ndarray
    damping_speed: np.ndarray
    mass: float
    com_height: float
    leg_length: float
    foot_separation: float
    sensors: RobotSensors
    control: tuple[tuple[str, float], ...] = ()
    ik: tuple[tuple[str, float], ...] = ()
    soft_joint_fraction: float = 0.9
    flight_scale: float = 1.0
    step_width: float | None = None
    run_contact_length: float = math.inf
    step_time_scale: float = 1.0
    max_stride: float | None = None
    swing_height: float | None = None
    max_yaw_rate: float | None = None
    source: str = ""
    standing_computed: bool = field(default=False)

    #: Names of the sole sites the IK adds to the model.
    SOLE_SITES = _mj.SOLE_SITES

    def _key(self) -> tuple[Any, ...]:
        return (
            self.name,
            str(self.mjcf),
            self.source,
            self.standing_pose,
            self.sole_offsets,
            self.sole_quats,
            self.sensors,
        )

    def __hash__(self) -> int:
        return hash(self._key())

    def __eq__(self, other: object) -> bool:
        return isinstance(other, RobotConfig) and self._key() == other._key()

    # ------------------------------------------------------------------ model
    def model(self, scene: bool = False) -> Any:
        """The compiled ``mujoco.MjModel`` with the two sole sites added (cached).

        ``scene=True`` adds a floor, a light and a larger offscreen buffer for rendering.
        """
        return _compile(self.mjcf, self.sole_bodies, self._site_poses(), scene, self.sensors)

    @property
    def imu_site(self) -> str:
        """The IMU site's name (:class:`gaitshift.robots.sensors.ImuMount`)."""
        return self.sensors.imu.site

    def _site_poses(self) -> tuple[Any, ...]:
        return tuple(zip(self.sole_offsets, self.sole_quats, strict=True))

    def add_sites(self, spec: Any) -> None:
        """Add the sole sites and the sensors' sites (a body-mounted IMU, a depth camera) to an
        ``MjSpec`` of this robot's MJCF (the plant builds its own model)."""
        _mj.add_sole_sites(spec, self.mjcf, self.sole_bodies, self._site_poses())
        self.sensors.add_sites(spec)

    def standing_qpos(self, model: Any = None) -> np.ndarray:
        """qpos of the standing pose: base at the origin, upright, joints from ``standing_pose``."""
        return _mj.standing_qpos(model if model is not None else self.model(), self.standing_pose)

    def speed_limits(self) -> tuple[np.ndarray, list[str]]:
        """The smaller of ``velocity_limit`` and ``damping_speed`` of each joint (J,) rad/s, and where each
        comes from (text)."""
        lim = np.minimum(self.velocity_limit, self.damping_speed)
        src = [
            "torque limit / joint damping of the MJCF" if d < v else "velocity_limits of the robot YAML"
            for v, d in zip(self.velocity_limit, self.damping_speed, strict=True)
        ]
        return lim, src

    def facts(self) -> RobotFacts:
        """The numbers scenarios default from (:class:`gaitshift.scenario.facts.RobotFacts`)."""
        return RobotFacts(
            self.name,
            self.mass,
            self.com_height,
            self.leg_length,
            (float(self.sole_size[0]), float(self.sole_size[1])),
            self.foot_separation,
        )

    def summary(self) -> dict[str, Any]:
        """Plain numbers for printing and for ``meta``."""
        return {
            "name": self.name,
            "mjcf": str(self.mjcf),
            "mass": round(self.mass, 3),
            "com_height": round(self.com_height, 4),
            "leg_length": round(self.leg_length, 4),
            "foot_separation": round(self.foot_separation, 4),
            "sole_size": [round(float(x), 4) for x in self.sole_size],
            "joints": len(self.joint_names),
            "foot_roll": list(self.foot_roll),
        }


# ====================================================================== loading
def builtin_robots() -> list[str]:
    """Names of the robot configs shipped with gaitshift."""
    folder = resources.files("gaitshift.robots") / "configs"
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".yaml"))


def load_robot(name_or_yaml: str | Path | RobotConfig) -> RobotConfig:
    """Load a robot config from a built-in name (``g1``, ``t1``, ...) or a YAML path.

    Raises:
        InputError: unknown name (the message lists the built-in names), no such file, unreadable
            file, bad YAML, a missing key (named alone), a bad value (named by its dotted field), or
            names that are not in the model.
    """
    if isinstance(name_or_yaml, RobotConfig):
        return name_or_yaml
    key = str(name_or_yaml)
    names = builtin_robots()
    if key in names:
        text = (resources.files("gaitshift.robots") / "configs" / f"{key}.yaml").read_text()
        return _load_text(text, None, key)
    path = Path(key)
    if path.suffix.lower() not in (".yaml", ".yml"):
        raise InputError("robot", key, "a built-in robot (" + ", ".join(names) + ") or a robot YAML file")
    text = yaml_text(path, "robot", "a built-in robot (" + ", ".join(names) + ")", InputError)
    return _load_text(text, str(path.resolve().parent), str(path.resolve()))


def _check_names(model: Any, cfg: RobotYaml, mjcf: Path) -> None:
    import mujoco

    for fld in ("hips", "knees", "leg_joints", "arm_joints", "standing_pose", "velocity_limits"):
        for n in getattr(cfg, fld):
            if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, n) < 0:
                raise InputError(f"robot.{fld}", n, f"a joint of {mjcf.name}")
    for fld, n in (
        ("torso", cfg.torso),
        ("soles.left.body", cfg.soles.left.body),
        ("soles.right.body", cfg.soles.right.body),
    ):
        if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, n) < 0:
            raise InputError(f"robot.{fld}", n, f"a body of {mjcf.name}")
    if set(cfg.leg_joints) & set(cfg.standing_pose) and cfg.com_height is not None:
        raise InputError(
            "robot.com_height", cfg.com_height, "only when standing_pose gives no leg joint (the legs set the height)"
        )


def _joints(model: Any, mjcf: Path) -> list[int]:
    import mujoco

    free = [j for j in range(model.njnt) if int(model.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_FREE)]
    if len(free) != 1 or model.jnt_qposadr[free[0]] != 0:
        raise InputError("robot.mjcf", str(mjcf), "a floating-base humanoid (one free joint, first)")
    kinds = (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE))
    joints = [j for j in range(model.njnt) if int(model.jnt_type[j]) in kinds]
    if len(joints) != model.njnt - 1:
        raise InputError("robot.mjcf", str(mjcf), "hinge or slide joints besides the free joint")
    return joints


def _leg_ids(model: Any, cfg: RobotYaml) -> list[list[int]]:
    """Joint ids of each leg: the leg joints on the path from the base to each sole body."""
    legs = []
    for sole in (cfg.soles.left.body, cfg.soles.right.body):
        b, chain = model.body(sole).id, set()
        while b > 0:
            chain.add(b)
            b = int(model.body_parentid[b])
        legs.append([model.joint(n).id for n in cfg.leg_joints if int(model.jnt_bodyid[model.joint(n).id]) in chain])
    return legs


@functools.lru_cache(maxsize=16)
def _load_text(text: str, base: str | None, source: str) -> RobotConfig:
    raw = yaml_mapping(text, "robot", source, "robot keys (name, mjcf, soles, ...)", InputError)
    try:
        cfg = RobotYaml.model_validate(raw)
    except ValidationError as exc:
        raise input_error(exc, RobotYaml, prefix="robot.") from None
    mjcf = _mj.resolve_mjcf(cfg.mjcf, base)
    raw_model = _mj.raw_model(mjcf)
    _check_names(raw_model, cfg, mjcf)
    joints = _joints(raw_model, mjcf)
    bodies = [raw_model.body(s.body).id for s in (cfg.soles.left, cfg.soles.right)]
    quats = _sole_quats(cfg)
    soles = tuple(
        sole_geometry(raw_model, b, q, s.pos)
        for b, q, s in zip(bodies, quats, (cfg.soles.left, cfg.soles.right), strict=True)
    )
    sole_quats = tuple(s.quat for s in soles)
    offsets = tuple(tuple(float(x) for x in s.centre) for s in soles)
    sole_bodies = (cfg.soles.left.body, cfg.soles.right.body)
    model = _compile(mjcf, sole_bodies, tuple(zip(offsets, sole_quats, strict=True)), False, None)
    legs = _leg_ids(model, cfg)
    knees = [model.joint(n).id for n in cfg.knees]
    roll = foot_roll(model, legs, knees, soles, bodies)  # type: ignore[arg-type]
    pose = dict(cfg.standing_pose)
    computed = not set(cfg.leg_joints) & set(pose)
    sites = (model.site(_mj.SOLE_SITES[0]).id, model.site(_mj.SOLE_SITES[1]).id)
    if computed:
        straight = com_height(model, ())
        height = cfg.com_height if cfg.com_height is not None else STANDING_HEIGHT_FRACTION * straight
        orientation = cfg.sole_orientation if isinstance(cfg.sole_orientation, str) else "quaternions"
        pose = computed_standing_pose(model, sites, legs, knees, list(roll), height, pose, orientation)
    names = tuple(model.joint(j).name for j in joints)
    rng = np.array([model.jnt_range[j] if model.jnt_limited[j] else (-np.inf, np.inf) for j in joints])
    for n, lo, hi in zip(names, rng[:, 0], rng[:, 1], strict=True):
        a = pose.get(n, float(model.qpos0[model.jnt_qposadr[model.joint(n).id]]))
        if not lo - 1e-9 <= a <= hi + 1e-9:
            raise InputError(f"robot.standing_pose.{n}", a, f"the joint range [{lo}, {hi}]")
    stand = tuple(pose.items())
    damping = np.array([_mj.damping_speed_limit(model, j) for j in joints])
    return RobotConfig(
        name=cfg.name,
        description=cfg.description,
        mjcf=mjcf,
        sole_bodies=sole_bodies,
        sole_offsets=offsets,  # type: ignore[arg-type]
        sole_quats=sole_quats,  # type: ignore[arg-type]
        soles=soles,  # type: ignore[arg-type]
        sole_size=cfg.sole_size if cfg.sole_size is not None else common_size(soles),
        torso=cfg.torso,
        base=model.body(model.jnt_bodyid[0]).name,
        hips=cfg.hips,
        knees=cfg.knees,
        leg_joints=cfg.leg_joints,
        arm_joints=cfg.arm_joints,
        foot_roll=roll,
        standing_pose=stand,
        velocity_limits_source=cfg.velocity_limits_source,
        joint_names=names,
        joint_range=rng,
        torque_limit=np.array([_mj.torque_limit(model, j) for j in joints]),
        velocity_limit=np.array([cfg.velocity_limits.get(n, np.inf) for n in names]),
        damping_speed=damping,
        mass=float(model.body_subtreemass[1]),
        com_height=com_height(model, stand),
        leg_length=leg_length(model, cfg.hips),
        foot_separation=foot_separation(model, stand),
        sensors=robot_sensors(cfg.sensors, raw_model, model.body(model.jnt_bodyid[0]).name),
        control=tuple(cfg.control.items()),
        ik=tuple((k, v) for k, v in cfg.ik.model_dump().items() if v is not None),
        soft_joint_fraction=cfg.limits.soft_joint_fraction,
        flight_scale=cfg.gait.flight_scale,
        step_width=cfg.gait.step_width,
        run_contact_length=cfg.gait.run_contact_length or math.inf,
        step_time_scale=cfg.gait.step_time_scale,
        max_stride=cfg.gait.max_stride,
        swing_height=cfg.gait.swing_height,
        max_yaw_rate=cfg.gait.max_yaw_rate,
        source=source,
        standing_computed=computed,
    )


def _sole_quats(cfg: RobotYaml) -> tuple[Any, Any]:
    o = cfg.sole_orientation
    if isinstance(o, str):
        return o, o
    return o.left, o.right


@functools.lru_cache(maxsize=8)
def _compile(
    mjcf: Path, sole_bodies: tuple[str, str], poses: tuple[Any, ...], scene: bool, sensors: RobotSensors | None
) -> Any:
    spec = _mj.load_spec(mjcf)
    _mj.add_sole_sites(spec, mjcf, sole_bodies, poses)
    if sensors is not None:
        sensors.add_sites(spec)
    if scene:
        _mj.add_render_scene(spec)
    return spec.compile()
