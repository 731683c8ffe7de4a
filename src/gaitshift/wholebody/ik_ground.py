"""The ground as an inequality of the whole-body IK (:mod:`gaitshift.wholebody.ik`): chosen corners of
a sole stay on or above the plan's terrain.

A corner c(q) of a sole (its centre +- L/2 along the sole's x axis, +- W/2 along its y axis; L, W the
robot's ``sole_size``) clears the ground by g(q) = c_z(q) - z(c_x(q)), z the terrain height
(:class:`~gaitshift.models.terrain.Terrain`, m). Linearised at q for the step dq of one QP of the IK:

    g(q) + (J_z - s J_x) dq >= 0,     s = dz/dx of the terrain at c_x,

the mink inequality G dq <= h with the row G = s J_x - J_z and h = g(q) (J: the translational Jacobian
(3, nv) of the corner point, ``mj_jac`` on the sole's body). Active per sample (:meth:`GroundLimit.hold`):

* the two heel corners of a sole pivoting about its toe (toe-off): its heel must rise, not dig into the
  ground (the toe corners are held on it by the toe point and the sole's roll);
* all four corners of a swing sole whose height is soft (``IKSettings.swing_lift_cost``), and of the soles
  of a flight whose poses are soft tasks (:meth:`gaitshift.wholebody.ik_tasks.SoleTaskSets.reaching`):
  pitched toe down just after lift-off, a swing sole would otherwise put its toe through the ground;
* the centre of such a swing sole on or above its planned height z_p: the row -J_z of the centre and
  h = c_z(q) - z_p (it may rise where its toe needs it, never sag below the plan's swing path).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gaitshift.models.terrain import Terrain

#: corners of a sole in its frame, in units of (L/2, W/2): toe left, toe right, heel left, heel right
CORNERS = np.array([[1.0, 1.0, 0.0], [1.0, -1.0, 0.0], [-1.0, 1.0, 0.0], [-1.0, -1.0, 0.0]])
HEEL = (2, 3)
ALL = (0, 1, 2, 3)


class GroundLimit:
    """The inequality of the module docstring for the sole sites ``sites`` (left, right) of ``model``,
    soles of ``sole_size`` (length, width) m on the ground ``terrain``. A mink limit (``limits=``)."""

    def __init__(self, model: Any, sites: list[int], sole_size: tuple[float, float], terrain: Terrain):
        import mink
        import mujoco

        self._mj_jac, self._constraint = mujoco.mj_jac, mink.Constraint
        self.model, self.sites, self.terrain = model, sites, terrain
        self.local = CORNERS * np.array([sole_size[0] / 2, sole_size[1] / 2, 0.0])
        self.bodies = [int(model.site_bodyid[s]) for s in sites]
        #: (side, corner indices) held above the ground in the current sample
        self.active: list[tuple[int, tuple[int, ...]]] = []
        #: (side, height m) of the sole centres held on or above a height in the current sample
        self.floor: list[tuple[int, float]] = []
        self._jacp, self._jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))

    def hold(self, pivot: Any, air: Any, floor: Any = (None, None)) -> None:
        """Activate the heel corners of the soles ``pivot`` (2,) bool and every corner of the soles ``air``
        (2,) bool; nothing otherwise. ``floor`` (2,): a height (m) the sole's centre must stay on or above,
        or None."""
        self.active = [(i, ALL if air[i] else HEEL) for i in (0, 1) if air[i] or pivot[i]]
        self.floor = [(i, float(z)) for i, z in enumerate(floor) if z is not None]

    def corners(self, data: Any, side: int) -> np.ndarray:
        """The four corners (4, 3) of sole ``side`` in the world, m."""
        s = self.sites[side]
        return np.asarray(data.site_xpos[s] + self.local @ data.site_xmat[s].reshape(3, 3).T)

    def compute_qp_inequalities(self, configuration: Any, dt: float) -> Any:
        """(G, h) of the active corners (module docstring); inactive when none."""
        del dt
        if not self.active and not self.floor:
            return self._constraint()
        d = configuration.data
        rows, h = [], []
        for side, z in self.floor:
            p = d.site_xpos[self.sites[side]]
            self._mj_jac(self.model, d, self._jacp, self._jacr, p, self.bodies[side])
            rows.append(-self._jacp[2])
            h.append(p[2] - z)
        for side, idx in self.active:
            pts = self.corners(d, side)
            for c in idx:
                p = pts[c]
                self._mj_jac(self.model, d, self._jacp, self._jacr, p, self.bodies[side])
                slope = float(self.terrain.slope(p[0]))
                rows.append(slope * self._jacp[0] - self._jacp[2])
                h.append(p[2] - float(self.terrain.height(p[0])))
        return self._constraint(G=np.array(rows), h=np.array(h))
