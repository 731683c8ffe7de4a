"""Foot contacts and ground reaction forces read from MuJoCo, and the fall test.

Contacts with the ground (``Plant.ground_geoms``: the floor, the terrain boxes and the bumps of
:mod:`gaitshift.sim.bumps`) are sorted by the robot geom involved: a sole sphere marks its foot as
touching and adds its contact force (``mj_contactForce``, rotated from the contact frame to the world
frame, sign chosen so that it is the force of the ground on the foot) to that foot's ground reaction
force; any other geom on the ground is a fall. The robot has also fallen when its pelvis is below
:data:`FALL_HEIGHT_FRACTION` of its initial height.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from gaitshift.sim.plant import Plant

FALL_HEIGHT_FRACTION = 0.6


@dataclass(frozen=True)
class FootContacts:
    """Contacts at one instant.

    Attributes:
        touching: (2,) bool, a sphere of the left/right sole is on the floor.
        grf: (2, 3) N, world-frame force of the floor on each foot (sum over its spheres).
        foreign: name of a body other than the soles that touches the floor, or None.
    """

    touching: np.ndarray
    grf: np.ndarray
    foreign: str | None


class ContactSensor:
    """Reads :class:`FootContacts` from ``MjData`` after ``mj_forward`` (see module docstring)."""

    def __init__(self, plant: Plant) -> None:
        self.plant = plant
        self.side_of = {g: s for s in (0, 1) for g in plant.soles[s].geoms}
        self.ground = frozenset(getattr(plant, "ground_geoms", ()) or (plant.floor_geom,))
        self._cf = np.zeros(6)

    def read(self, d: mujoco.MjData) -> FootContacts:
        m = self.plant.model
        ground = self.ground
        touching = np.zeros(2, bool)
        grf = np.zeros((2, 3))
        foreign = None
        for ci in range(d.ncon):
            con = d.contact[ci]
            g1, g2 = con.geom[0], con.geom[1]
            if g1 not in ground and g2 not in ground:
                continue
            other = g2 if g1 in ground else g1
            if other not in self.side_of:
                foreign = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, m.geom_bodyid[other])
                continue
            s = self.side_of[other]
            touching[s] = True
            mujoco.mj_contactForce(m, d, ci, self._cf)
            fw = con.frame.reshape(3, 3).T @ self._cf[:3]
            grf[s] += fw if other == g2 else -fw
        return FootContacts(touching=touching, grf=grf, foreign=foreign)


def fall_reason(contacts: FootContacts, pelvis_height: float, pelvis_height0: float) -> str | None:
    """Why the robot has fallen, or None: a non-sole body on the floor, or the pelvis height (m) below
    :data:`FALL_HEIGHT_FRACTION` of its initial height ``pelvis_height0`` (m)."""
    if contacts.foreign is not None:
        return f"{contacts.foreign} touched the floor"
    if pelvis_height < FALL_HEIGHT_FRACTION * pelvis_height0:
        return "pelvis below 60% of its initial height"
    return None
