"""The keys of a robot YAML file (validated with pydantic; unknown keys are errors).

=====================  ========================================================================
``name``               short name, e.g. ``g1``
``mjcf``               ``asset:<path>`` (inside the PyPI package envpool-assets-mujoco-playground-
                       humanoid, located offline with its ``asset_path()``), an absolute path, or a
                       path relative to the YAML file
``soles``              ``left``/``right``: ``{body: <foot body>, pos: [x, y, z]}``; ``pos`` (optional) is
                       the sole centre in the body frame, m; default: the centre of the lowest points
                       of the foot's collision geoms (:mod:`gaitshift.robots.soles`)
``sole_orientation``   (optional) sole frame in the foot body frame: ``body`` (default), ``geoms`` (the
                       frame of the foot's largest collision box) or ``{left: [w, x, y, z], right: ...}``
                       (each of norm >= :data:`MIN_QUAT_NORM`; normalised)
``sole_size``          (optional) [length, width] of the sole rectangle, m; default: from the geoms
``torso``              body kept upright by the IK
``hips``, ``knees``    [left, right] hip-pitch and knee joint names (reach and singularity checks)
``leg_joints``         the leg joints, left then right
``arm_joints``         (optional) joints held at the standing pose by the arm posture task
``standing_pose``      (optional) {joint: angle, rad}; unlisted joints are at the model's qpos0, except
                       when it gives no leg joint (arms only, or absent): the leg joints are then
                       computed by IK with the given joints held (:mod:`gaitshift.robots.standing`)
``com_height``         (optional, only when ``standing_pose`` gives no leg joint) CoM height above the
                       soles, m, for which the leg joints are computed;
                       default: 0.92 x the CoM height with straight legs
``velocity_limits``    (optional) {joint: rad/s}; MJCF has no velocity limits, so they come from the
                       maker's URDF (``velocity_limits_source`` says which); ``gaitshift robot check``
                       also checks torque limit / joint damping (:mod:`gaitshift.robots.mjcf`)
``control``            (optional) whole-body controller gains for this robot {name: value}; the names
                       are the fields of ``gaitshift.control.wbc.Gains`` (docs/robots.md)
``ik``                 (optional) weights of the whole-body IK's soft tasks for this robot: ``posture_cost``,
                       ``torso_cost``, ``arm_cost`` (fields of ``gaitshift.wholebody.ik.IKSettings``)
``limits``             (optional) ``soft_joint_fraction`` (0 < f <= 1, default 0.9): the soft range of each
                       joint is the middle f of its MJCF range (centre +- f x half range, as mjlab's
                       ``soft_joint_pos_limit_factor``); reference motions (``gaitshift export`` of a
                       plan) keep every joint inside it
``sensors``            (optional) the IMU frame, ``imu: {site: <site>}`` or ``imu: {body: <body>,
                       pos: [x, y, z], quat: [w, x, y, z]}`` (default: the floating base's origin), and
                       ``foot_force`` (default false): whether the soles measure force, and
                       ``depth_camera`` (optional): a depth camera's mount, field of view, pixels,
                       range, rate, noise and dropout (:mod:`gaitshift.robots.sensors`)
``gait``               (optional) how a scenario is scaled to this robot (:mod:`gaitshift.wholebody.scaling`):
                       ``flight_scale`` (0 < s <= 1) multiplies the TV-LIPM flight time of running steps
                       (a weaker robot lands softer: touchdown speed g T_f / 2); ``step_width`` (m) is the
                       lateral step width instead of the standing foot separation (docs/robots.md);
                       ``run_contact_length`` (m, optional) the longest distance the body travels over one
                       running stance: faster runs shorten the stance to it and lengthen the flight
                       (:mod:`gaitshift.gait.run_timing`, docs/simulation.md "Top speed");
                       ``step_time_scale`` (0 < s <= 1) multiplies the single and double support times
                       and the stride (quicker, shorter steps at the same speed: less lateral sway)
                       ``max_stride`` (m, optional) caps the stride of scaled scenarios (TV-LIPM
                       ``profile.max_stride``, VHIP ``limits.max_stride``; explicit footholds are kept);
                       ``swing_height`` (m, optional) the swing-foot clearance instead of lambda x the
                       scenario's (TV-LIPM ``swing_height``, VHIP ``swing_apex``);
                       ``max_yaw_rate`` (rad/s, optional) caps the turn rate of scaled live-command
                       (locomotion) scenarios (``limits.max_yaw_rate``)
=====================  ========================================================================
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, Strict, field_validator, model_validator

from gaitshift.scenario.fields import Length, Real, StrictModel

#: a joint angle, rad
Angle = Annotated[float, Strict(), Field(ge=-10, le=10, allow_inf_nan=False)]
#: a joint speed limit, rad/s
JointSpeed = Annotated[float, Strict(), Field(gt=0, le=1000, allow_inf_nan=False)]
#: a quaternion component
QuatPart = Annotated[float, Strict(), Field(ge=-1, le=1, allow_inf_nan=False)]
#: a controller gain or weight
Gain = Annotated[float, Strict(), Field(ge=0, le=1e6, allow_inf_nan=False)]


class Sole(StrictModel):
    body: str
    pos: tuple[Real, Real, Real] | None = None


class Soles(StrictModel):
    left: Sole
    right: Sole


#: smallest norm of a ``sole_orientation`` quaternion (a zero quaternion is no rotation)
MIN_QUAT_NORM = 0.1


class SoleQuats(StrictModel):
    left: tuple[QuatPart, QuatPart, QuatPart, QuatPart]
    right: tuple[QuatPart, QuatPart, QuatPart, QuatPart]


class Gait(StrictModel):
    """How scenarios are scaled to the robot (``gait`` key; :func:`gaitshift.wholebody.scaling.scale_scenario`)."""

    flight_scale: Annotated[float, Strict(), Field(gt=0, le=1, allow_inf_nan=False)] = 1.0
    step_width: Length | None = None
    run_contact_length: Length | None = None
    step_time_scale: Annotated[float, Strict(), Field(gt=0, le=1, allow_inf_nan=False)] = 1.0
    max_stride: Length | None = None
    swing_height: Length | None = None
    max_yaw_rate: Annotated[float, Strict(), Field(gt=0, le=20, allow_inf_nan=False)] | None = None


class Imu(StrictModel):
    """The IMU frame (``sensors.imu``): a site of the MJCF, or a body and an offset (not both)."""

    site: str | None = None
    body: str | None = None
    pos: tuple[Real, Real, Real] = (0.0, 0.0, 0.0)
    quat: tuple[QuatPart, QuatPart, QuatPart, QuatPart] = (1.0, 0.0, 0.0, 0.0)

    @model_validator(mode="after")
    def _one_place(self) -> Imu:
        if self.site is not None and (self.body is not None or self.pos != (0.0, 0.0, 0.0)):
            raise ValueError("either a site, or a body with pos and quat (not both)")
        if sum(x * x for x in self.quat) ** 0.5 < MIN_QUAT_NORM:
            raise ValueError(f"a quaternion [w, x, y, z] of norm >= {MIN_QUAT_NORM} ({list(self.quat)} is no rotation)")
        return self


FovAngle = Annotated[float, Strict(), Field(gt=0, lt=3.1, allow_inf_nan=False)]
Pixels = Annotated[int, Strict(), Field(ge=1, le=256)]
NonNegative = Annotated[float, Strict(), Field(ge=0, le=10, allow_inf_nan=False)]


class DepthCameraSettings(StrictModel):
    """A depth camera (``sensors.depth_camera``; :class:`gaitshift.robots.sensors.DepthCamera`)."""

    body: str
    pos: tuple[Real, Real, Real] = (0.0, 0.0, 0.0)
    quat: tuple[QuatPart, QuatPart, QuatPart, QuatPart] = (1.0, 0.0, 0.0, 0.0)
    fov: tuple[FovAngle, FovAngle]
    pixels: tuple[Pixels, Pixels] = (32, 24)
    range: tuple[Length, Length]
    rate: Annotated[float, Strict(), Field(gt=0, le=1000, allow_inf_nan=False)] = 30.0
    noise: tuple[NonNegative, NonNegative] = (0.0, 0.0)
    dropout: Annotated[float, Strict(), Field(ge=0, lt=1, allow_inf_nan=False)] = 0.0

    @model_validator(mode="after")
    def _ordered(self) -> DepthCameraSettings:
        if not self.range[0] < self.range[1]:
            raise ValueError(f"range [min, max] with min < max (got {list(self.range)})")
        if sum(x * x for x in self.quat) ** 0.5 < MIN_QUAT_NORM:
            raise ValueError(f"a quaternion [w, x, y, z] of norm >= {MIN_QUAT_NORM} ({list(self.quat)} is no rotation)")
        return self


class Sensors(StrictModel):
    """What the robot measures (``sensors`` key; :mod:`gaitshift.robots.sensors`)."""

    imu: Imu = Field(default_factory=Imu)
    foot_force: Annotated[bool, Strict()] = False
    depth_camera: DepthCameraSettings | None = None


class IkWeights(StrictModel):
    """Soft-task weights of the whole-body IK for the robot (``ik`` key; unset: the IKSettings defaults)."""

    posture_cost: Gain | None = None
    torso_cost: Gain | None = None
    arm_cost: Gain | None = None


class Limits(StrictModel):
    """Joint-range margins (``limits`` key): the soft range is the middle ``soft_joint_fraction`` of each range."""

    soft_joint_fraction: Annotated[float, Strict(), Field(gt=0, le=1, allow_inf_nan=False)] = 0.9


class RobotYaml(StrictModel):
    """The keys of a robot YAML file (see module docstring)."""

    name: str
    description: str = ""
    mjcf: str
    soles: Soles
    sole_orientation: Literal["body", "geoms"] | SoleQuats = "body"
    sole_size: tuple[Length, Length] | None = None
    torso: str
    hips: tuple[str, str]
    knees: tuple[str, str]
    leg_joints: tuple[str, ...]
    arm_joints: tuple[str, ...] = ()
    standing_pose: dict[str, Angle] = Field(default_factory=dict)
    com_height: Length | None = None
    velocity_limits: dict[str, JointSpeed] = Field(default_factory=dict)
    velocity_limits_source: str = ""
    control: dict[str, Gain] = Field(default_factory=dict)
    gait: Gait = Field(default_factory=Gait)
    sensors: Sensors = Field(default_factory=Sensors)
    ik: IkWeights = Field(default_factory=IkWeights)
    limits: Limits = Field(default_factory=Limits)

    @field_validator("sole_orientation")
    @classmethod
    def _unit_quats(cls, value: object) -> object:
        if isinstance(value, SoleQuats):
            for side in ("left", "right"):
                q = getattr(value, side)
                if sum(x * x for x in q) ** 0.5 < MIN_QUAT_NORM:
                    raise ValueError(
                        f"a quaternion [w, x, y, z] of norm >= {MIN_QUAT_NORM} per side "
                        f"({side}: {list(q)} is no rotation)"
                    )
        return value
