"""The robot in a viser scene: its MuJoCo geoms (meshes and primitives) posed from ``MjData``.

Two builders, chosen by name in :data:`SCENES` (measured against each other in ``docs/web.md``):

- ``mjviser``: :class:`mjviser.ViserMujocoScene`, which merges the geoms of each body, shares
  identical geometry between bodies, and sends the poses of all bodies of a mesh group in one
  batched message per group;
- ``viser``: plain viser, one mesh node per moving body (its visible geoms merged, in the body
  frame) and one pose (position, quaternion w x y z) per body and update.

Both follow the robot the same way: the whole scene is translated by ``-x_pelvis`` (the first moving
body's world position, m), so the camera keeps the robot in view. Overlays drawn in world
coordinates go under :attr:`RobotScene.root`, a frame that carries this translation.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

import mujoco
import numpy as np

__all__ = ["SCENES", "RobotScene", "build_scene"]


class RobotScene(Protocol):
    """A robot drawn in a viser server.

    Attributes:
        root: scene path of the frame that holds world-frame overlays (it moves with the scene).
    """

    root: str

    def update(self, d: mujoco.MjData) -> None:
        """Pose every moving body from ``d`` (after ``mj_forward``: ``xpos`` (nbody, 3), ``xquat``
        (nbody, 4) w x y z) and translate the scene by minus the tracked body's position."""


def _moving_bodies(m: mujoco.MjModel) -> list[int]:
    """Bodies that move: those with a non-world root body that has joints (or a free root)."""
    return [b for b in range(1, m.nbody) if m.body_weldid[m.body_rootid[b]] != 0 or m.body_mocapid[b] >= 0]


class MjviserScene:
    """``mjviser``'s scene on ``server`` for model ``m``; overlays under ``/fixed_bodies/gaitshift``."""

    def __init__(self, server: Any, m: mujoco.MjModel) -> None:
        from mjviser import ViserMujocoScene

        self.scene = ViserMujocoScene(server, m, num_envs=1)
        self.root = "/fixed_bodies/gaitshift"
        server.scene.add_frame(self.root, show_axes=False)

    def update(self, d: mujoco.MjData) -> None:
        """Batched poses of the mesh groups (one message per group)."""
        self.scene.update_from_mjdata(d)


def _geom_mesh(m: mujoco.MjModel, g: int) -> Any:
    """Geom ``g`` as a trimesh in its body's frame (mesh, box, sphere, capsule, cylinder, ellipsoid),
    or None for a type this view does not draw (planes are drawn as the grid)."""
    import trimesh

    t, size = int(m.geom_type[g]), m.geom_size[g]
    gt = mujoco.mjtGeom
    mesh: Any
    if t == gt.mjGEOM_MESH:
        k = int(m.geom_dataid[g])
        v0, nv, f0, nf = m.mesh_vertadr[k], m.mesh_vertnum[k], m.mesh_faceadr[k], m.mesh_facenum[k]
        mesh = trimesh.Trimesh(m.mesh_vert[v0 : v0 + nv].copy(), m.mesh_face[f0 : f0 + nf].copy(), process=False)
    elif t == gt.mjGEOM_BOX:
        mesh = trimesh.creation.box(extents=2 * size)
    elif t == gt.mjGEOM_SPHERE:
        mesh = trimesh.creation.icosphere(subdivisions=2, radius=size[0])
    elif t == gt.mjGEOM_CAPSULE:
        mesh = trimesh.creation.capsule(height=2 * size[1], radius=size[0])
    elif t == gt.mjGEOM_CYLINDER:
        mesh = trimesh.creation.cylinder(radius=size[0], height=2 * size[1])
    elif t == gt.mjGEOM_ELLIPSOID:
        mesh = trimesh.creation.icosphere(subdivisions=2, radius=1.0)
        mesh.apply_scale(size)
    else:
        return None
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, m.geom_quat[g])
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = rot.reshape(3, 3), m.geom_pos[g]
    mesh.apply_transform(pose)
    rgba = m.mat_rgba[m.geom_matid[g]] if m.geom_matid[g] >= 0 else m.geom_rgba[g]
    mesh.visual.face_colors = np.tile((np.clip(rgba, 0, 1) * 255).astype(np.uint8), (len(mesh.faces), 1))
    return mesh


class ViserScene:
    """Plain viser: one node per moving body, posed one by one (module docstring)."""

    def __init__(self, server: Any, m: mujoco.MjModel) -> None:
        import trimesh

        self.server = server
        self.root = "/world"
        self.frame = server.scene.add_frame(self.root, show_axes=False)
        server.scene.add_grid(f"{self.root}/floor", width=40.0, height=40.0, cell_size=0.5, section_size=1.0)
        self.bodies = _moving_bodies(m)
        self.tracked = self.bodies[0] if self.bodies else 0
        self.nodes: list[tuple[int, Any]] = []
        for b in self.bodies:
            geoms = [
                g for g in range(m.ngeom) if m.geom_bodyid[g] == b and m.geom_rgba[g, 3] > 0 and m.geom_group[g] < 3
            ]
            meshes = [x for x in (_geom_mesh(m, g) for g in geoms) if x is not None]
            if meshes:
                name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b) or f"body{b}"
                node = server.scene.add_mesh_trimesh(f"{self.root}/robot/{name}", trimesh.util.concatenate(meshes))
                self.nodes.append((b, node))

    def update(self, d: mujoco.MjData) -> None:
        """One pose per body node, sent in one atomic batch."""
        with self.server.atomic():
            self.frame.position = -d.xpos[self.tracked]
            for b, node in self.nodes:
                node.position = d.xpos[b]
                node.wxyz = d.xquat[b]
        self.server.flush()


#: scene builder name -> class taking (viser server, MjModel)
SCENES: dict[str, Callable[[Any, mujoco.MjModel], RobotScene]] = {"mjviser": MjviserScene, "viser": ViserScene}


def build_scene(name: str, server: Any, m: mujoco.MjModel) -> RobotScene:
    """The scene builder ``name`` of :data:`SCENES` on ``server`` for model ``m``.

    Raises:
        InputError: unknown name.
    """
    from gaitshift.errors import InputError

    if name not in SCENES:
        raise InputError("web backend", name, " or ".join(SCENES))
    return SCENES[name](server, m)
