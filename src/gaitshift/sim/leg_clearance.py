"""Do the robot's two legs touch each other? The truth, read from MuJoCo for the metrics.

Two checks, because the robot models collide only part of a foot:

* **legs touch**: MuJoCo has a contact between a collision geom of the left leg and one of the right
  leg. A leg is the subtree of the body below the lowest common ancestor of the two sole bodies on
  the path to that sole (for the G1: the hip-pitch link and everything under it), taken from the
  model's kinematic tree.
* **feet overlap**: the two soles' footprints (rectangles of the robot YAML's sole size, centred on
  the sole frames, projected on the horizontal plane) intersect (separating-axis test on the four
  edge directions) while the higher sole is less than the foot's depth ``h_f`` above the lower one.
  ``h_f`` is the distance of the sole plane below the origin of its foot body (the ankle joint of the
  G1, 0.035 m), so a sole that high or higher is above the other foot's body. The G1's foot body
  collides with the floor through four sole spheres only: two feet passing through each other are
  not a MuJoCo contact, and this test is what sees them. Higher up, the ankle and shank meshes do
  collide, and "legs touch" sees them.

Neither is told to the controller: the step limits that keep feet apart
(:mod:`gaitshift.control.step_limits`) are checked against these, the physics.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np

from gaitshift.sim.plant import Plant

__all__ = ["LegClearance", "footprints_overlap", "leg_bodies"]


def leg_bodies(model: mujoco.MjModel, feet: tuple[int, int]) -> tuple[frozenset[int], frozenset[int]]:
    """Body ids of each leg (module docstring) for the foot bodies ``feet`` (left, right)."""
    chains = []
    for b in feet:
        chain = [b]
        while chain[-1] != 0:
            chain.append(int(model.body_parentid[chain[-1]]))
        chains.append(chain)
    common = next(b for b in chains[0] if b in chains[1])
    roots = [chain[chain.index(common) - 1] for chain in chains]
    legs = []
    for root in roots:
        members = {root}
        for b in range(root + 1, model.nbody):  # MuJoCo orders bodies depth first: children after parents
            if int(model.body_parentid[b]) in members:
                members.add(b)
        legs.append(frozenset(members))
    return legs[0], legs[1]


def footprints_overlap(centres: np.ndarray, axes: np.ndarray, half: np.ndarray) -> bool:
    """Whether two rectangles in the plane intersect (separating-axis theorem).

    Args:
        centres: (2, 2) m, the rectangles' centres.
        axes: (2, 2) unit vectors, each rectangle's long axis (its short axis is the long one turned
            by +90 degrees).
        half: (2,) m, half length and half width (the same for both).
    """
    frames = [np.array([a, [-a[1], a[0]]]) for a in axes]  # rows: long axis, short axis
    d = centres[1] - centres[0]
    for f in frames:
        for n in f:
            reach = sum(abs(float(n @ g[0])) * half[0] + abs(float(n @ g[1])) * half[1] for g in frames)
            if abs(float(n @ d)) >= reach:
                return False
    return True


@dataclass(frozen=True)
class LegClearance:
    """The two checks of the module docstring on one plant.

    Attributes:
        plant: the plant; leg_of: (nbody,) the leg of each body (0 left, 1 right, -1 neither); half:
            the sole's half length and half width, m; depth: ``h_f``, m.
    """

    plant: Plant
    leg_of: np.ndarray
    half: np.ndarray
    depth: float

    @classmethod
    def of(cls, plant: Plant) -> LegClearance:
        """The checks for ``plant``: legs from its kinematic tree, footprint from its robot's YAML."""
        soles = plant.soles
        depth = float(np.mean([abs((s.rotation.T @ s.centre)[2]) for s in soles]))
        half = np.asarray(plant.robot.sole_size, float) / 2
        leg_of = np.full(plant.model.nbody, -1)
        for side, members in enumerate(leg_bodies(plant.model, (soles[0].body, soles[1].body))):
            leg_of[sorted(members)] = side
        return cls(plant, leg_of, half, depth)

    def legs_touch(self, d: mujoco.MjData) -> bool:
        """A MuJoCo contact between the two legs in ``d`` (after ``mj_forward``)."""
        if d.ncon == 0:
            return False
        legs = self.leg_of[self.plant.model.geom_bodyid[d.contact.geom[: d.ncon]]]  # (ncon, 2)
        return bool(np.any((legs[:, 0] >= 0) & (legs[:, 1] >= 0) & (legs[:, 0] != legs[:, 1])))

    def feet_overlap(self, frames: Sequence[tuple[np.ndarray, np.ndarray]]) -> bool:
        """The feet pass through each other (module docstring), given both sole ``frames`` (left,
        right) as :meth:`Plant.sole_frame` gives them: centre (3,) m and rotation (3, 3)."""
        (c0, r0), (c1, r1) = frames
        if abs(float(c0[2] - c1[2])) >= self.depth:
            return False
        if float(np.hypot(c0[0] - c1[0], c0[1] - c1[1])) >= 2.0 * float(np.hypot(*self.half)):
            return False  # farther apart than the two footprints' circumscribed circles
        axes = np.array([r[:2, 0] / max(float(np.linalg.norm(r[:2, 0])), 1e-9) for r in (r0, r1)])
        return footprints_overlap(np.array([c0[:2], c1[:2]]), axes, self.half)

    def read(self, d: mujoco.MjData, frames: Sequence[tuple[np.ndarray, np.ndarray]]) -> np.ndarray:
        """(2,) bool: legs touch in ``d``, feet overlap at the sole ``frames`` of ``d``."""
        return np.array([self.legs_touch(d), self.feet_overlap(frames)])
