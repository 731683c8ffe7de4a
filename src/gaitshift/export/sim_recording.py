"""Rerun recording (``.rrd``) of a closed-loop run: what was measured next to what was planned.

Same timeline (``time``, the plan's clock, one row per control tick) and layout as the plan's
recording (:mod:`gaitshift.export.recording`), with measured and reference values side by side:

================================================  ==============================================
``timeseries/com/{x,y,z}``, ``com_ref/...``       measured CoM (``subtree_com``), tracked reference, m
``timeseries/zmp/{x,y}``                          the plan's ZMP at the tick's plan sample, m
``timeseries/feet/{left,right}/{x,y,z}``          measured sole centres, m
``timeseries/grf/{left,right}/{x,y,z}``           measured contact forces, N; ``grf_ref/...`` the QP's
``timeseries/speed/{commanded,reference,measured}``  |command| (where the plan has one), |reference
                                                  CoM velocity|, |measured CoM velocity|, m/s
``timeseries/gait``, ``/phase``, ``events/...``   the plan's gait and phase at the tick's plan sample
``timeseries/contact/{left,right}``               measured contact, 0/1
``world/com``, ``world/feet/...``                 as for a plan (measured)
``world/footsteps``                               the planned footholds, each set from the tick the
                                                  controller's plan changed them on (a re-plan: a
                                                  perceived run's footholds move onto the map)
``world/support``                                 convex hull of the soles in measured contact
``world/bodies/<body>``                           every body frame, FK of the logged qpos
``world/elevation_map``                           a robot with a depth camera: the controller's map
                                                  over time, its seen cells at their heights (coloured
                                                  by height, one scale for the run), every
                                                  ``1 / MAP_RATE`` s (:mod:`gaitshift.sim.log`) and
                                                  as the run ended, at the last tick
``world/elevation_map/edges``                     its edge cells (a step of more than
                                                  :data:`~gaitshift.control.perception.EDGE_STEP` to a
                                                  neighbour), red, larger, at the same times
``world/scan``                                    each depth frame the controller fused, from its
                                                  tick on: the points placed with the ESTIMATED
                                                  camera pose (the brain's view), m
``timeseries/map/{left,right}``                   the map's height under each true sole centre, m
================================================  ==============================================

3D frames (body frames, support polygons) are drawn at ``FRAME_RATE`` Hz.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.common.atomic import atomic_path
from gaitshift.export.recording import (
    FRAME_RATE,
    GAITS,
    PHASES,
    Recording,
    check_rrd,
    frame_indices,
    scenario_name,
    support_polygon,
)

#: the scan's points' radius, m
SCAN_RADIUS = 0.008


def record_simulation(result: Any, traj: Any, robot: Any, out: str | Path) -> dict[str, Any]:
    """Write the recording of the run ``result`` (a :class:`~gaitshift.sim.result.SimResult`) of the
    plan ``traj`` on ``robot`` (RobotConfig) to ``out`` (.rrd), atomically.

    Returns:
        ``ticks``, ``frames`` and ``bodies`` logged.
    """
    out = check_rrd(Path(out))
    a = result.arrays
    t = a["t"]
    i = np.clip(a["plan_index"], 0, len(traj.t) - 1)
    idx = frame_indices(t, FRAME_RATE)
    names, pos, quat, soles = _body_frames(robot, a["qpos"][idx])
    with atomic_path(out) as tmp:
        rec = Recording(tmp, scenario_name(result.meta.get("plan_meta", {}), "simulation"))
        rec.xyz("timeseries/com", t, a["com_pos"])
        rec.xyz("timeseries/com_ref", t, a["com_ref"])
        rec.xyz("timeseries/zmp", t, traj.zmp[i], "xy")
        for s, side in enumerate(("left", "right")):
            rec.xyz(f"timeseries/feet/{side}", t, a["foot_pos"][:, s])
            rec.xyz(f"timeseries/grf/{side}", t, a["grf"][:, s])
            rec.xyz(f"timeseries/grf_ref/{side}", t, a["grf_ref"][:, s])
            rec.series(f"timeseries/contact/{side}", t, a["contact"][:, s].astype(float))
            color = [40, 110, 240] if s == 0 else [240, 140, 30]
            rec.points(f"world/feet/{side}", t, a["foot_pos"][:, s], 0.02, color)
        rec.series("timeseries/speed/commanded", t, np.linalg.norm(traj.command_vel[i], axis=1))
        rec.series("timeseries/speed/reference", t, np.linalg.norm(a["com_vel_ref"][:, :2], axis=1))
        rec.series("timeseries/speed/measured", t, np.linalg.norm(a["com_vel"][:, :2], axis=1))
        rec.series("timeseries/gait", t, traj.gait[i].astype(float))
        rec.series("timeseries/phase", t, traj.phase[i].astype(float))
        rec.events("events/gait", t, traj.gait[i], GAITS)
        rec.events("events/phase", t, traj.phase[i], PHASES)
        rec.points("world/com", t, a["com_pos"], 0.03, [220, 30, 30])
        _footholds(rec, a, traj, robot.sole_size)
        polys = [
            support_polygon(soles[f, :, 0], soles[f, :, 1, 0], a["contact"][k], robot.sole_size)
            for f, k in enumerate(idx)
        ]
        rec.polygons("world/support", t[idx], polys)
        rec.frames(names, t[idx], pos, quat)
        if "map_heights" in a:
            _elevation_map(rec, a)
        if "scan_t" in a:
            from gaitshift.control.perception import SCAN_COLOR

            counts = np.bincount(a["scan_frame"], minlength=len(a["scan_t"]))
            rec.clouds("world/scan", a["scan_t"], a["scan_points"], counts, SCAN_RADIUS, SCAN_COLOR)
        rec.close()
    return {"ticks": len(t), "frames": len(idx), "bodies": len(names)}


def _elevation_map(rec: Recording, a: dict[str, np.ndarray]) -> None:
    """The controller's map over the run (its snapshots, then the map as the run ended), coloured by
    height on one scale for the whole run, and its height under the soles over the run."""
    from gaitshift.control.perception import seen_cells

    t = a["t"]
    for s, side in enumerate(("left", "right")):
        rec.series(f"timeseries/map/{side}", t, np.where(a["map_known"][:, s], a["map_height"][:, s], np.nan))
    maps = []
    if "map_t" in a:  # a log written before the snapshots has the final map only
        maps = [(float(tk), a["map_cells"][a["map_cells_set"] == k], a["map_cells_edge"][a["map_cells_set"] == k])
                for k, tk in enumerate(a["map_t"])]  # fmt: skip
    r = float(a["map_resolution"])
    final, _, edge = seen_cells(a["map_heights"], a["map_seen"].astype(bool), a["map_corner"], r)
    maps.append((float(t[-1]), final, edge))
    z = np.concatenate([cells[:, 2] for _, cells, _ in maps])
    if not len(z):
        return
    lo, span = float(z.min()), max(float(np.ptp(z)), 1e-3)
    for tk, cells, edge in maps:
        _map_cells(rec, tk, np.asarray(cells, dtype=float), edge, (cells[:, 2] - lo) / span, r)


def _map_cells(rec: Recording, tk: float, cells: np.ndarray, edge: np.ndarray, shade: np.ndarray, r: float) -> None:
    """One map at plan time ``tk`` s: its seen cells ``cells`` (N, 3) m coloured by ``shade`` (N,) in
    [0, 1], and its edge cells (``edge`` (N,) bool) in red, larger. An entity with no cell at ``tk`` is
    cleared, so that scrubbing the timeline never shows an older map's cells as the current ones."""
    from matplotlib import colormaps

    from gaitshift.control.perception import EDGE_COLOR

    colors = (255 * colormaps["viridis"](shade)[:, :3]).astype(np.uint8)
    rec.cloud("world/elevation_map", tk, cells, colors, r / 2)
    red = np.full((int(edge.sum()), 3), EDGE_COLOR, dtype=np.uint8)
    rec.cloud("world/elevation_map/edges", tk, cells[edge], red, 0.7 * r)


def _footholds(rec: Recording, a: dict[str, np.ndarray], traj: Any, size: tuple[float, float]) -> None:
    """Each logged set of planned footholds from its time on; the final plan's, static, for a log
    without them."""
    if "footholds_t" not in a:
        rec.soles("world/footsteps", traj.footsteps, traj.footstep_side, size)
        return
    for g, tg in enumerate(a["footholds_t"]):
        mine = a["footholds_set"] == g
        rec.soles("world/footsteps", a["footholds"][mine], a["footholds_side"][mine], size, float(tg))


def _body_frames(robot: Any, qpos: np.ndarray) -> tuple[list[str], np.ndarray, np.ndarray, np.ndarray]:
    """Body names, positions (F, B, 3), quaternions (F, B, 4) and sole poses (F, 2, 2, 3): per foot
    the sole centre (m) and (yaw, 0, 0) (rad, the heading of the sole's x axis), by FK of ``qpos``."""
    import mujoco

    from gaitshift.export.kinematics import body_names, body_states

    model = robot.model()
    states = body_states(model, qpos, np.zeros((len(qpos), model.nv)))
    data = mujoco.MjData(model)
    sites = [model.site(n).id for n in robot.SOLE_SITES]
    soles = np.zeros((len(qpos), 2, 2, 3))
    for k, q in enumerate(qpos):
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        for s, sid in enumerate(sites):
            x_axis = data.site_xmat[sid].reshape(3, 3)[:, 0]
            soles[k, s, 0] = data.site_xpos[sid]
            soles[k, s, 1, 0] = np.arctan2(x_axis[1], x_axis[0])
    return body_names(model), states["body_pos_w"], states["body_quat_w"], soles
