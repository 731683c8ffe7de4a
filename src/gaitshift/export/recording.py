"""Rerun recordings (``.rrd``) of a plan: timelines, the robot's body frames and the support polygons.

Timeline ``time`` (s, the plan's clock). Entities, SI units:

=================================  =========================================================
``timeseries/com/{x,y,z}``         CoM position, m (every sample)
``timeseries/zmp/{x,y}``           ZMP, m (samples with a foot on the ground)
``timeseries/feet/{left,right}/z`` sole centre height, m (x and y likewise)
``timeseries/grf/total/{x,y,z}``   total ground reaction force m (c̈ + g e_z), N (robot known)
``timeseries/speed/commanded``     |commanded horizontal velocity|, m/s (where commanded)
``timeseries/speed/com``           |horizontal CoM velocity|, m/s
``timeseries/gait``, ``/phase``    gait 0 stand 1 walk 2 run; phase 0 DS 1 SS 2 flight
``events/gait``, ``events/phase``  text at each change (``walk``, ``SS``, ...)
``world/com``, ``world/zmp``       3D points; ``world/feet/{left,right}`` sole centres
``world/footsteps``                every foothold, a sole-sized box (static)
``world/support``                  support polygon: convex hull of the soles on the ground
``world/bodies/<body>``            body frame (world pose, MuJoCo order) with axes
=================================  =========================================================

The body frames come from the whole-body IK at ``FRAME_RATE`` Hz (or the nearest 1/(k dt)) when the
plan names a robot (or one is given); the support polygons are drawn at that rate too.
Read a file with ``rerun FILE.rrd`` (viewer) or ``rerun.chunk.RrdReader`` (SDK).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.common.atomic import atomic_path, check_suffix
from gaitshift.errors import InfeasibleError, InputError

#: rate of the 3D frames (body frames, support polygons), Hz
FRAME_RATE = 50.0
GAITS = ("stand", "walk", "run")
PHASES = ("DS", "SS", "F")


def rerun_module() -> Any:
    """The ``rerun`` module.

    Raises:
        InputError: rerun-sdk is not installed.
    """
    try:
        import rerun
    except ImportError:
        raise InputError("--rerun", "rerun-sdk", "rerun-sdk installed (pip install 'gaitshift[view]')") from None
    return rerun


def check_rrd(path: Path) -> Path:
    """Check an ``--rerun`` file name (and that rerun-sdk is there) before any work.

    Raises:
        InputError: not a .rrd name, or rerun-sdk missing.
    """
    check_suffix(path, "--rerun", (".rrd",))
    rerun_module()
    return Path(path)


class Recording:
    """A Rerun recording stream saved to a file, with the few shapes of data gaitshift logs."""

    def __init__(self, path: Path, name: str) -> None:
        self.rr = rerun_module()
        self.rec = self.rr.RecordingStream("gaitshift", recording_id=name)
        self.rec.save(str(path))

    def close(self) -> None:
        """Flush everything to the file."""
        self.rec.flush()
        self.rec.disconnect()

    def _time(self, t: np.ndarray) -> list[Any]:
        return [self.rr.TimeColumn("time", duration=np.asarray(t, float))]

    def series(self, entity: str, t: np.ndarray, values: np.ndarray) -> None:
        """A scalar timeline; samples where ``values`` is not finite are left out."""
        ok = np.isfinite(values)
        if ok.any():
            cols = self.rr.Scalars.columns(scalars=np.asarray(values, float)[ok])
            self.rec.send_columns(entity, indexes=self._time(t[ok]), columns=cols)

    def xyz(self, entity: str, t: np.ndarray, values: np.ndarray, axes: str = "xyz") -> None:
        """One scalar timeline per axis: ``entity/x``, ``entity/y``, ..."""
        for i, axis in enumerate(axes):
            self.series(f"{entity}/{axis}", t, values[:, i])

    def points(self, entity: str, t: np.ndarray, pos: np.ndarray, radius: float, color: Any) -> None:
        """A moving 3D point (rows with a non-finite coordinate are left out)."""
        ok = np.all(np.isfinite(pos), axis=1)
        self.rec.log(entity, self.rr.Points3D.from_fields(radii=radius, colors=color), static=True)
        if ok.any():
            cols = self.rr.Points3D.columns(positions=pos[ok])
            self.rec.send_columns(entity, indexes=self._time(t[ok]), columns=cols)

    def cloud(self, entity: str, t: float, pos: np.ndarray, colors: np.ndarray, radius: float) -> None:
        """A point cloud (N, 3) with colours (N, 3) uint8, shown from time ``t`` s on."""
        self.rec.set_time("time", duration=float(t))
        self.rec.log(entity, self.rr.Points3D(pos, colors=colors, radii=radius))

    def events(self, entity: str, t: np.ndarray, codes: np.ndarray, names: tuple[str, ...]) -> None:
        """A text event at each change of the integer ``codes`` (named by ``names``)."""
        change = np.flatnonzero(np.r_[True, codes[1:] != codes[:-1]])
        for k in change:
            self.rec.set_time("time", duration=float(t[k]))
            self.rec.log(entity, self.rr.TextLog(names[int(codes[k])]))

    def frames(self, names: list[str], t: np.ndarray, pos: np.ndarray, quat_wxyz: np.ndarray) -> None:
        """Body frames ``world/bodies/<name>``: positions (F, B, 3), quaternions (F, B, 4)."""
        for b, name in enumerate(names):
            entity = f"world/bodies/{name}"
            self.rec.log(entity, self.rr.TransformAxes3D(0.08), static=True)
            cols = self.rr.Transform3D.columns(translation=pos[:, b], quaternion=quat_wxyz[:, b][:, [1, 2, 3, 0]])
            self.rec.send_columns(entity, indexes=self._time(t), columns=cols)

    def polygons(self, entity: str, t: np.ndarray, polygons: list[np.ndarray]) -> None:
        """A closed polygon (n, 3) per time (empty: nothing on the ground)."""
        for tk, poly in zip(t, polygons, strict=True):
            self.rec.set_time("time", duration=float(tk))
            strips = [np.vstack([poly, poly[:1]])] if len(poly) else []
            self.rec.log(entity, self.rr.LineStrips3D(strips, colors=[40, 160, 60]))

    def soles(
        self, entity: str, steps: np.ndarray, sides: np.ndarray, size: tuple[float, float], t: float | None = None
    ) -> None:
        """Footholds (M, 4: x, y, z m, yaw rad) as flat sole-sized boxes: static, or shown from time
        ``t`` s on (until the next set logged on ``entity``)."""
        half = [size[0] / 2, size[1] / 2, 0.002]
        quats = [self.rr.Quaternion(xyzw=[0, 0, math.sin(y / 2), math.cos(y / 2)]) for y in steps[:, 3]]
        colors = [[40, 110, 240] if s == 0 else [240, 140, 30] for s in sides]
        boxes = self.rr.Boxes3D(centers=steps[:, :3], half_sizes=[half] * len(steps), quaternions=quats, colors=colors)
        if t is None:
            self.rec.log(entity, boxes, static=True)
        else:
            self.rec.set_time("time", duration=float(t))
            self.rec.log(entity, boxes)

    def clouds(
        self, entity: str, t: np.ndarray, pos: np.ndarray, counts: np.ndarray, radius: float, color: Any
    ) -> None:
        """A point cloud per time ``t`` (F,) s: the first ``counts[0]`` rows of ``pos`` (P, 3) m at
        ``t[0]``, the next ``counts[1]`` at ``t[1]``, ... (one colour, ``radius`` m)."""
        self.rec.log(entity, self.rr.Points3D.from_fields(radii=radius, colors=color), static=True)
        cols = self.rr.Points3D.columns(positions=pos).partition(np.asarray(counts, dtype=np.int64))
        self.rec.send_columns(entity, indexes=self._time(t), columns=cols)


def support_polygon(feet: np.ndarray, yaw: np.ndarray, down: np.ndarray, size: tuple[float, float]) -> np.ndarray:
    """Convex hull (n, 3), counter-clockwise, of the sole rectangles (``size`` = length, width, m) of
    the feet with ``down`` true, centred at ``feet`` (2, 3) with heading ``yaw`` (2,); (0, 3) if none."""
    from scipy.spatial import ConvexHull

    corners = []
    for i in np.flatnonzero(down):
        c, s = math.cos(yaw[i]), math.sin(yaw[i])
        for dx, dy in ((1, 1), (-1, 1), (-1, -1), (1, -1)):
            x, y = dx * size[0] / 2, dy * size[1] / 2
            corners.append([feet[i, 0] + c * x - s * y, feet[i, 1] + s * x + c * y, feet[i, 2]])
    if not corners:
        return np.zeros((0, 3))
    pts = np.array(corners)
    if len(pts) == 4:
        return pts
    return np.asarray(pts[ConvexHull(pts[:, :2]).vertices], dtype=float)


def frame_indices(t: np.ndarray, rate: float) -> np.ndarray:
    """Sample indices nearest to t_0 + k / rate."""
    times = np.arange(t[0], t[-1] + 1e-9, 1.0 / rate)
    return np.unique(np.clip(np.searchsorted(t, times - 1e-9), 0, len(t) - 1))


def record_plan(traj: Any, out: str | Path, robot: Any = None) -> dict[str, Any]:
    """Write the Rerun recording of the plan ``traj`` to ``out`` (.rrd), atomically (see module
    docstring). ``robot``: a RobotConfig for the body frames and GRF (else the plan's robot, if any).

    Returns:
        what was logged: ``samples``, ``frames`` and ``bodies`` (0 when the whole-body IK was not
        run or failed: then ``note`` says why).
    """
    out = check_rrd(Path(out))
    robot = robot if robot is not None else _plan_robot(traj)
    bodies: tuple[list[str], np.ndarray, np.ndarray, np.ndarray] | None = None
    note = "no robot named by the plan" if robot is None else ""
    if robot is not None:
        try:
            bodies = _ik_frames(traj, robot)
        except InfeasibleError as exc:
            note = f"whole-body IK failed: {exc}"
    with atomic_path(out) as tmp:
        rec = Recording(tmp, scenario_name(traj.meta, "plan"))
        _plan_timelines(rec, traj, robot)
        idx = frame_indices(traj.t, FRAME_RATE)
        size = tuple(traj.meta["foot_size"])
        polys = [support_polygon(traj.foot_pos[k], traj.foot_yaw[k], traj.contact[k], size) for k in idx]
        rec.polygons("world/support", traj.t[idx], polys)
        if bodies is not None:
            rec.frames(bodies[0], bodies[1], bodies[2], bodies[3])
        if note:
            rec.rec.log("events/notes", rec.rr.TextLog(note), static=True)
        rec.close()
    return {"samples": len(traj.t), "frames": len(idx), "bodies": 0 if bodies is None else len(bodies[0]), "note": note}


def scenario_name(meta: dict[str, Any], default: str) -> str:
    """The scenario name a plan's ``meta`` holds (``meta.scenario`` is its name or its dict)."""
    scenario = meta.get("scenario")
    return str(scenario.get("name", default) if isinstance(scenario, dict) else scenario or default)


def _plan_robot(traj: Any) -> Any:
    from gaitshift.api import named_robot
    from gaitshift.robots.config import load_robot

    name = named_robot(traj.meta)
    if name is None:
        return None

    return load_robot(str(name))


def _ik_frames(traj: Any, robot: Any) -> tuple[list[str], np.ndarray, np.ndarray, np.ndarray]:
    """Body names, times, positions and quaternions of the IK solution at about FRAME_RATE Hz."""
    from gaitshift.export.kinematics import body_names, body_states
    from gaitshift.wholebody.ik import WholeBodyIK

    step = max(1, round(1.0 / (traj.dt * FRAME_RATE)))
    joints = WholeBodyIK(robot).solve(traj, rate=1.0 / (step * traj.dt), check_velocities=False)
    model = robot.model()
    states = body_states(model, joints.qpos, joints.qvel)
    return body_names(model), joints.t, states["body_pos_w"], states["body_quat_w"]


def _plan_timelines(rec: Recording, traj: Any, robot: Any) -> None:
    t = traj.t
    rec.xyz("timeseries/com", t, traj.com_pos)
    rec.xyz("timeseries/zmp", t, traj.zmp, "xy")
    for i, side in enumerate(("left", "right")):
        rec.xyz(f"timeseries/feet/{side}", t, traj.foot_pos[:, i])
        rec.points(f"world/feet/{side}", t, traj.foot_pos[:, i], 0.02, [40, 110, 240] if i == 0 else [240, 140, 30])
    if robot is not None:
        g = float(traj.meta.get("gravity", 9.81))
        rec.xyz("timeseries/grf/total", t, robot.mass * (traj.com_acc + np.array([0.0, 0.0, g])))
    rec.series("timeseries/speed/commanded", t, np.linalg.norm(traj.command_vel, axis=1))
    rec.series("timeseries/speed/com", t, np.linalg.norm(traj.com_vel[:, :2], axis=1))
    rec.series("timeseries/gait", t, traj.gait.astype(float))
    rec.series("timeseries/phase", t, traj.phase.astype(float))
    rec.events("events/gait", t, traj.gait, GAITS)
    rec.events("events/phase", t, traj.phase, PHASES)
    rec.points("world/com", t, traj.com_pos, 0.03, [220, 30, 30])
    rec.points("world/zmp", t, traj.zmp, 0.025, [30, 200, 60])
    rec.soles("world/footsteps", traj.footsteps, traj.footstep_side, tuple(traj.meta["foot_size"]))
