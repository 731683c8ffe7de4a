"""The log of a closed-loop run: preallocated arrays, one row per control tick; and the events between
ticks: the elevation map's snapshots (:class:`PerceptionLog`), the depth scans the controller fused
(:class:`ScanLog`) and each new set of planned footholds (:class:`FootholdLog`)."""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np

from gaitshift.control.perception import seen_cells, thin_scan
from gaitshift.control.wbc_data import TickInfo, TickReference
from gaitshift.sim.contacts import FootContacts


class TickLog:
    """Arrays of ``n_ticks`` rows (world frame, SI), in file order:

    ``t`` (plan time, s), ``qpos`` (nq), ``qvel`` (nv), ``tau`` (nu, N m applied), ``com_pos``,
    ``com_ref`` (tracked: plan + shift), ``com_vel``, ``com_vel_ref`` (3), ``contact`` (measured) and
    ``contact_ref`` (planned) (2, bool), ``stance`` (controller, 2 bool), ``grf`` (measured) and
    ``grf_ref`` (QP) (2, 3) N, ``foot_pos`` (measured) and ``foot_ref`` (2, 3) sole centres, ``angmom``
    (3, centroidal angular momentum, kg m^2/s), ``plan_index`` (plan sample), ``com_shift`` (3, plan
    shift of the step feedback), ``qp_ok`` (bool), ``push_force`` (3, N on the pelvis), ``legs_touch`` and
    ``feet_overlap`` (bool, :mod:`gaitshift.sim.leg_clearance`).
    """

    def __init__(self, n_ticks: int, model: mujoco.MjModel) -> None:
        n = n_ticks  # rows grow on demand beyond this (:meth:`record`)
        self.data: dict[str, np.ndarray] = {
            "t": np.zeros(n),
            "qpos": np.zeros((n, model.nq)),
            "qvel": np.zeros((n, model.nv)),
            "tau": np.zeros((n, model.nu)),
            "com_pos": np.zeros((n, 3)),
            "com_ref": np.zeros((n, 3)),
            "com_vel": np.zeros((n, 3)),
            "com_vel_ref": np.zeros((n, 3)),
            "contact": np.zeros((n, 2), bool),
            "contact_ref": np.zeros((n, 2), bool),
            "stance": np.zeros((n, 2), bool),
            "grf": np.zeros((n, 2, 3)),
            "grf_ref": np.zeros((n, 2, 3)),
            "foot_pos": np.zeros((n, 2, 3)),
            "foot_ref": np.zeros((n, 2, 3)),
            "angmom": np.zeros((n, 3)),
            "plan_index": np.zeros(n, np.int64),
            "com_shift": np.zeros((n, 3)),
            "qp_ok": np.zeros(n, bool),
            "push_force": np.zeros((n, 3)),
            "legs_touch": np.zeros(n, bool),
            "feet_overlap": np.zeros(n, bool),
        }

    def record(
        self,
        k: int,
        t: float,
        i: int,
        d: mujoco.MjData,
        tau: np.ndarray,
        contacts: FootContacts,
        ref: TickReference,
        info: TickInfo,
        shift: np.ndarray,
        contact_ref: np.ndarray,
        foot_pos: np.ndarray,
        push: np.ndarray,
        clearance: np.ndarray,
    ) -> None:
        """Row ``k``: plan time ``t``, plan sample ``i``, the state in ``d`` (after ``mj_forward`` and
        ``mj_subtreeVel``, before the step), the torques, contacts, reference and QP result, and the
        legs' ``clearance`` (2,) bool (legs touch, feet overlap)."""
        a = self.data
        if k >= len(a["t"]):
            self._grow(2 * len(a["t"]))
        a["t"][k] = t
        a["qpos"][k] = d.qpos
        a["qvel"][k] = d.qvel
        a["tau"][k] = tau
        a["com_pos"][k] = d.subtree_com[0]
        a["com_ref"][k] = ref.com_pos
        a["com_shift"][k] = shift
        a["com_vel"][k] = d.subtree_linvel[0]
        a["com_vel_ref"][k] = ref.com_vel
        a["contact"][k] = contacts.touching
        a["contact_ref"][k] = contact_ref
        a["stance"][k] = ref.stance
        a["grf"][k] = contacts.grf
        a["grf_ref"][k] = info.forces
        a["foot_pos"][k] = foot_pos
        a["foot_ref"][k] = ref.foot_pos
        a["angmom"][k] = d.subtree_angmom[0]
        a["plan_index"][k] = i
        a["qp_ok"][k] = info.ok
        a["push_force"][k] = push
        a["legs_touch"][k], a["feet_overlap"][k] = clearance

    def _grow(self, n: int) -> None:
        """More rows (a run longer than allocated: a live session); new pushes are zero."""
        for key, v in self.data.items():
            grown = np.zeros((n, *v.shape[1:]), dtype=v.dtype)
            grown[: len(v)] = v
            self.data[key] = grown

    def arrays(self, n: int) -> dict[str, np.ndarray]:
        """The first ``n`` rows of every array (the ticks run)."""
        return {key: v[:n] for key, v in self.data.items()}


class EstimationLog:
    """Per tick: the controller's state estimate (used by it or not,
    :class:`~gaitshift.control.state.EstimateRecord`), prefixed ``est_`` in the run's arrays:
    ``est_qpos`` (nq), ``est_qvel`` (nv), ``est_contact`` (the fused contact), ``est_stance`` (the
    force-confirmed stance the controller's scheduler gets), ``est_slip`` (2, bool), ``est_com``,
    ``est_com_vel`` (3), ``est_mu`` (friction assumed), ``est_tick_us`` (estimator cost, µs; 0 at
    tick 0, the known start state)."""

    KEYS = ("qpos", "qvel", "contact", "stance", "slip", "com", "com_vel", "mu", "tick_us")

    def __init__(self) -> None:
        self.rows: dict[str, list[Any]] = {k: [] for k in self.KEYS}

    def record(self, estimate: Any) -> None:
        """One row from an :class:`~gaitshift.control.state.EstimateRecord`."""
        for key, rows in self.rows.items():
            rows.append(np.array(getattr(estimate, key), copy=True))

    def arrays(self, n: int) -> dict[str, np.ndarray]:
        """The first ``n`` rows as arrays named ``est_<key>`` (none when no estimator ran)."""
        if not self.rows["qpos"]:
            return {}
        return {f"est_{k}": np.array(v[:n]) for k, v in self.rows.items()}


#: the elevation map's snapshots per second of plan time (:class:`PerceptionLog`): the browser view's
#: redraw rate too (``MAP_EVERY`` frames of its 30 per second), Hz
MAP_RATE = 2.0


class PerceptionLog:
    """Per tick: the controller's elevation map read at the TRUE soles' centres (a metric reads the
    controller's output against the truth; the controller never sees this): ``map_height`` (2,) m and
    ``map_known`` (2,) bool (the cell has been seen). The map over time, a snapshot of its seen cells
    every ``1 / MAP_RATE`` s of plan time from the first tick: ``map_t`` (K,) plan time s of each,
    ``map_cells`` (C, 3) float32 m (each seen cell's centre at its height, world frame),
    ``map_cells_edge`` (C,) bool (a step of more than ``EDGE_STEP`` to a neighbour) and ``map_cells_set``
    (C,) int32, the snapshot each cell belongs to. And the map as the run ended: ``map_heights`` (n, n) m
    (0 where unseen), ``map_seen`` (n, n) bool, ``map_corner`` (2,) m (the world xy of cell [0, 0]'s lower
    corner) and ``map_resolution`` m. Empty when the robot has no depth camera."""

    def __init__(self) -> None:
        self.height: list[np.ndarray] = []
        self.known: list[np.ndarray] = []
        self.snapshots: list[tuple[float, np.ndarray, np.ndarray]] = []
        self._last: Any = None

    def record(self, tp: float, elevation_map: Any, soles_xy: np.ndarray) -> None:
        """At plan time ``tp`` s, one row: the map's height and whether it is known under each sole
        (``soles_xy`` (2, 2) m); and a snapshot of the map when ``1 / MAP_RATE`` s have passed since the
        last."""
        h, p = elevation_map.lookup(soles_xy)
        self.height.append(h)
        self.known.append(np.isfinite(p))
        self._last = elevation_map
        if not self.snapshots or tp >= self.snapshots[-1][0] + 1.0 / MAP_RATE - 1e-9:
            m = elevation_map
            cells, _, edge = seen_cells(m.height, m.known, m.corner * m.settings.resolution, m.settings.resolution)
            self.snapshots.append((tp, cells.astype(np.float32), edge))

    def _final(self) -> dict[str, np.ndarray]:
        m = self._last
        r = m.settings.resolution
        return {
            "map_heights": np.where(m.known, m.height, 0.0),
            "map_seen": m.known.copy(),
            "map_corner": m.corner * r,
            "map_resolution": np.array(r),
            "map_t": np.array([t for t, _, _ in self.snapshots]),
            "map_cells": np.concatenate([c for _, c, _ in self.snapshots]).reshape(-1, 3),
            "map_cells_edge": np.concatenate([e for _, _, e in self.snapshots]).astype(bool),
            "map_cells_set": group_index([c for _, c, _ in self.snapshots]),
        }

    def arrays(self, n: int) -> dict[str, np.ndarray]:
        """The first ``n`` rows, or nothing when no map was logged."""
        if not self.height:
            return {}
        return {"map_height": np.array(self.height[:n]), "map_known": np.array(self.known[:n]), **self._final()}


def group_index(groups: list[np.ndarray]) -> np.ndarray:
    """(sum of the lengths,) int32: the index of the group each row of ``np.concatenate(groups)`` comes from."""
    return np.repeat(np.arange(len(groups), dtype=np.int32), [len(g) for g in groups])


class ScanLog:
    """The depth camera's scans as the controller placed them (:attr:`Perceiver.scan
    <gaitshift.control.perception.perceiver.Perceiver.scan>`: the frame's points put into the world
    with the camera pose of the ESTIMATED state; the brain's view, never the world's truth), one per
    frame fused: ``scan_t`` (F,) plan time s of the tick that fused each frame, ``scan_points`` (P, 3)
    float32 m (world frame, z up; at most :data:`~gaitshift.control.perception.SCAN_POINTS` a frame,
    ``thin_scan``) and ``scan_frame`` (P,) int32, the frame each point belongs to. Empty when the robot
    has no depth camera."""

    def __init__(self) -> None:
        self.t: list[float] = []
        self.points: list[np.ndarray] = []
        self._frames = 0

    def record(self, tp: float, perceiver: Any) -> None:
        """At plan time ``tp`` s: the perceiver's last scan, if it fused a frame since the last call."""
        if perceiver.frames == self._frames:
            return
        self._frames = perceiver.frames
        self.t.append(tp)
        self.points.append(thin_scan(perceiver.scan))

    def arrays(self) -> dict[str, np.ndarray]:
        """Every scan logged, or nothing (no camera, or no frame fused)."""
        if not self.t:
            return {}
        return {
            "scan_t": np.asarray(self.t),
            "scan_points": np.concatenate(self.points),
            "scan_frame": group_index(self.points),
        }


class FootholdLog:
    """The planned footholds each time the controller's plan changed them (a driver's re-plans, a
    perceived run's moves onto the map): ``footholds_t`` (G,) plan time s of each set,
    ``footholds`` (S, 4) (x, y, z m world frame, yaw rad), ``footholds_side`` (S,) int8 (0 left,
    1 right) and ``footholds_set`` (S,) int32, the set each foothold belongs to. The first set is the
    plan's at the first tick."""

    def __init__(self) -> None:
        self.t: list[float] = []
        self.sets: list[tuple[np.ndarray, np.ndarray]] = []
        self._traj: Any = None

    def record(self, tp: float, traj: Any) -> None:
        """At plan time ``tp`` s: the plan ``traj``'s footholds, if they differ from the last set."""
        if traj is self._traj:
            return
        self._traj = traj
        steps = np.array(traj.footsteps, dtype=float).reshape(-1, 4)
        if self.sets and np.array_equal(steps, self.sets[-1][0]):
            return
        self.t.append(tp)
        self.sets.append((steps, np.array(traj.footstep_side, dtype=np.int8)))

    def arrays(self) -> dict[str, np.ndarray]:
        """Every set, or nothing when none was recorded."""
        if not self.sets:
            return {}
        return {
            "footholds_t": np.asarray(self.t),
            "footholds": np.concatenate([s for s, _ in self.sets]),
            "footholds_side": np.concatenate([side for _, side in self.sets]),
            "footholds_set": group_index([steps for steps, _ in self.sets]),
        }
