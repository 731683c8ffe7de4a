"""One case, run inside a worker process: plain dicts in, plain dicts out.

:func:`run_case` takes the case (:mod:`gaitshift.campaign.cases`) and its validated scenario (a
pydantic object), builds every MuJoCo object it needs in the calling process and returns
``{"row": {...}, "motion": {...} | None}``: the result row (:data:`METRICS` columns, numbers or None,
never NaN) and, for the ``reference`` task, the whole-body motion as numpy arrays (``t`` (N,) s,
``qpos`` (N, nq), ``qvel`` (N, nv), ``meta`` JSON text). So nothing from MuJoCo crosses a process
boundary. A :class:`~gaitshift.errors.GaitshiftError` of the case itself (an infeasible plan, a joint
over its speed limit) is a result: its row carries ``error`` and no metrics.

Metrics (simulate and closed-loop reference): ``fell``, ``t_fall`` (s of plan time), ``speed_error``
(RMS of the stride-mean velocity error, m/s, :mod:`gaitshift.sim.tracking`), ``heading_error`` (RMS
pelvis yaw error, rad), ``flight_ratio`` (achieved / planned flight), ``peak_torque_fraction`` (max
|tau| / tau_max), ``joint_speed_fraction`` (max |q̇_j| / limit_j over joints with a limit; for plans:
of the whole-body IK at 100 Hz), ``steps_completed`` / ``steps_planned``, ``plan_gaits`` (the gaits
the plan uses, "walk", "run" or "walk+run"), ``fall_reason`` (what touched the floor),
``fall_cause`` (crossing, slip, estimate, torque or reach, :mod:`gaitshift.sim.fall_cause`),
``legs_touch_time`` and ``feet_overlap_time`` (s the
two legs touched each other, :mod:`gaitshift.sim.leg_clearance`), ``plan_duration`` and
``sim_time`` (s), ``end_x`` (m, the true pelvis's x at the end), ``replans`` (re-plans the plan
driver made) and ``replans_refused`` (those a perceived driver did not take), the elevation map's
numbers when the robot has a depth camera (:mod:`gaitshift.sim.perception_metrics`: ``map_frames``,
``map_coverage``, ``map_error_median`` / ``_p95`` and ``frame_error_median`` / ``_p95`` m under the
standing soles, ``edge_distance_min`` / ``_median`` m from a standing sole to the nearest step edge,
``perception_stopped``: why a perceived walk stopped before an edge), ``wall_time`` and ``cpu_time``
(s of this process for the whole case: elapsed, and CPU time of the process, which is what a shared
machine's load does not inflate).
"""

from __future__ import annotations

import json
import math
import time
from typing import Any

import numpy as np

import gaitshift
from gaitshift.errors import GaitshiftError

__all__ = ["METRICS", "MOTIONS", "PERCEPTION", "RUNNERS", "edited_scenario", "run_case", "sim_options"]

#: result columns besides the case's parameters, and their Arrow types
METRICS: dict[str, str] = {
    "fell": "bool",
    "t_fall": "float64",
    "speed_error": "float64",
    "heading_error": "float64",
    "flight_ratio": "float64",
    "peak_torque_fraction": "float64",
    "joint_speed_fraction": "float64",
    "steps_completed": "int64",
    "steps_planned": "int64",
    "legs_touch_time": "float64",
    "feet_overlap_time": "float64",
    "plan_gaits": "string",
    "plan_duration": "float64",
    "sim_time": "float64",
    "fall_reason": "string",
    "fall_cause": "string",
    "contact_accuracy": "float64",
    "base_vel_rmse": "float64",
    "tilt_rmse": "float64",
    "end_x": "float64",
    "replans": "int64",
    "replans_refused": "int64",
    "map_frames": "int64",
    "map_coverage": "float64",
    "map_error_median": "float64",
    "map_error_p95": "float64",
    "frame_error_median": "float64",
    "frame_error_p95": "float64",
    "edge_distance_min": "float64",
    "edge_distance_median": "float64",
    "perception_stopped": "string",
    "wall_time": "float64",
    "cpu_time": "float64",
    "gaitshift_version": "string",
    "error": "string",
    "motion_file": "string",
}


#: the :mod:`gaitshift.sim.perception_metrics` numbers copied into a row under the same names
PERCEPTION = (
    "map_coverage", "map_error_median", "map_error_p95", "frame_error_median", "frame_error_p95",
    "edge_distance_min", "edge_distance_median",
)  # fmt: skip


def _finite(x: Any) -> float | None:
    return float(x) if x is not None and math.isfinite(float(x)) else None


def edited_scenario(sc: Any, case: dict[str, Any]) -> Any:
    """The scenario with the case's locomotion edits: ``speed`` scales every velocity command so that
    the largest |vx| equals it (all vx = speed when every vx is 0), ``yaw_rate`` replaces every
    velocity command's yaw rate, ``gait`` the gait, ``duration`` the ``stop_at``; re-validated."""
    if sc.planner != "locomotion":
        return sc
    data = sc.model_dump()
    cmds = [c for c in data["commands"] if c.get("goto") is None]
    if case["speed"] is not None:
        top = max((abs(c["vx"]) for c in cmds), default=0.0)
        for c in cmds:
            c["vx"] = float(c["vx"] * case["speed"] / top) if top > 0 else float(case["speed"])
    if case["yaw_rate"] is not None:
        for c in cmds:
            c["yaw_rate"] = float(case["yaw_rate"])
    if case["gait"] is not None:
        data["gait"] = case["gait"]
    if case["duration"] is not None:
        data["stop_at"] = float(case["duration"])
    return type(sc).model_validate(data)


def sim_options(case: dict[str, Any], cfg: Any) -> dict[str, Any]:
    """The case's simulation options (None: the scenario's ``sim:`` key, else the default; ``terrain``
    is what the planner is told, as ``simulate --terrain``); a push of the case replaces the scenario's
    pushes. A ``push_velocity`` v becomes the impulse ``s M v`` N s,
    ``M`` the robot's mass (kg, from its model) and ``s`` the case's mass scale."""
    from gaitshift.sim.pushes import Push

    keys = (
        "state", "noise", "noise_scale", "latency", "friction", "seed", "mass_scale", "contact", "motor_strength",
        "terrain",
    )  # fmt: skip
    out = {k: case[k] for k in keys} | {"control_period": case["control_period"]}
    out["com_offset"] = (case["com_offset_x"], case["com_offset_y"], case["com_offset_z"])
    impulse = case["push_impulse"] + case["push_velocity"] * case["mass_scale"] * float(cfg.model().body_mass.sum())
    if impulse > 0:
        a = math.radians(case["push_direction"])
        direction = (math.cos(a), math.sin(a))
        out["pushes"] = (Push(case["push_time"], impulse, case["push_duration"], direction),)
    return out


def _plan_facts(traj: Any) -> dict[str, Any]:
    """The plan's duration (s) and the gaits it uses besides standing ("walk", "run", "walk+run")."""
    from gaitshift.sim.metrics import GAITS

    used = [GAITS[g] for g in sorted(set(np.unique(traj.gait).tolist()) - {0})]
    return {"plan_duration": float(traj.t[-1]), "plan_gaits": "+".join(used) or "stand"}


def _joint_speed_fraction(cfg: Any, qvel: np.ndarray) -> float | None:
    lim = cfg.velocity_limit
    if len(qvel) == 0 or not np.any(np.isfinite(lim)):
        return None
    model = cfg.model()
    vadr = np.array([model.jnt_dofadr[model.joint(n).id] for n in cfg.joint_names])
    ok = np.isfinite(lim)
    return float(np.max(np.abs(qvel[:, vadr[ok]]) / lim[ok]))


def _simulate(sc: Any, cfg: Any, case: dict[str, Any]) -> tuple[dict[str, Any], Any]:
    """Closed-loop run of the case: its metrics and the result (arrays for a reference motion)."""
    from gaitshift.sim.scenario_run import simulate_scenario

    run = simulate_scenario(sc, cfg, **sim_options(case, cfg))
    res = run.result
    m = res.metrics
    row = {
        "fell": bool(res.fell),
        "t_fall": _finite(res.fall_time) if res.fell else None,
        "speed_error": _finite(m.get("stride_speed_error_rms")),
        "heading_error": _finite(m.get("heading_error_rms")),
        "flight_ratio": _finite(m.get("flight_ratio")),
        "peak_torque_fraction": _finite(m.get("peak_torque_fraction")),
        "joint_speed_fraction": _joint_speed_fraction(cfg, res.arrays["qvel"]),
        "steps_completed": int(m.get("steps_completed", 0)),
        "steps_planned": int(m.get("steps_planned", 0)),
        "legs_touch_time": _finite(m.get("legs_touch_time")),
        "feet_overlap_time": _finite(m.get("feet_overlap_time")),
        **_plan_facts(run.trajectory),
        "sim_time": float(res.meta["sim_time_s"]),
        **_estimate_row(m),
        **_perception_row(run),
    }
    return row, res


def _perception_row(run: Any) -> dict[str, Any]:
    """Where the run ended and what its plan driver and elevation map did (None where the run has none:
    no driver that re-plans, no depth camera, no step edge)."""
    res = run.result
    p = res.metrics.get("perception") or {}
    row = {k: _finite(p.get(k)) for k in PERCEPTION}
    refused = getattr(run.driver, "refused", None)
    return row | {
        "end_x": float(res.arrays["qpos"][-1, 0]) if len(res.arrays["qpos"]) else None,
        "replans": int(res.meta.get("replans", 0)),
        "replans_refused": None if refused is None else int(refused),
        "map_frames": int(p["frames"]) if "frames" in p else None,
        "perception_stopped": p.get("stopped"),
    }


def _estimate_row(metrics: dict[str, Any]) -> dict[str, Any]:
    """The fall's reason and the estimate's quality (None where the run has none)."""
    est = metrics.get("estimation") or {}
    return {
        "fall_reason": metrics.get("fall_reason") or None,
        "fall_cause": metrics.get("fall_cause"),
        "contact_accuracy": _finite(est.get("contact_accuracy")),
        "base_vel_rmse": _finite(est.get("base_vel_rmse")),
        "tilt_rmse": _finite(est.get("tilt_rmse")),
    }


def _plan(sc: Any, cfg: Any, _case: dict[str, Any]) -> tuple[dict[str, Any], Any]:
    """The kinematic plan of the case: its size and the joint speeds of its whole-body IK."""
    from gaitshift.api import plan
    from gaitshift.sim.metrics import touchdowns
    from gaitshift.wholebody.checks import peak_joint_speeds

    traj = plan(sc)
    peak = peak_joint_speeds(cfg, traj)
    lim = cfg.velocity_limit
    ok = np.isfinite(lim)
    frac = float(np.max(peak[ok] / lim[ok])) if peak is not None and np.any(ok) else None
    n = len(touchdowns(traj))
    row = {"joint_speed_fraction": frac, "steps_planned": n, **_plan_facts(traj)}
    return row, traj


def _ik_motion(case: dict[str, Any], cfg: Any, traj: Any) -> tuple[Any, Any, Any]:
    """t, qpos, qvel of the plan's whole-body IK at the case's reference rate (a divisor of the plan's)."""
    from gaitshift.wholebody.ik import IKSettings, WholeBodyIK

    k = max(1, round(1.0 / (float(case["reference_rate"]) * traj.dt)))
    jt = WholeBodyIK(cfg, IKSettings()).solve(traj, 1.0 / (k * traj.dt), check_velocities=False)
    return jt.t, jt.qpos, jt.qvel


def _sim_motion(case: dict[str, Any], _cfg: Any, res: Any) -> tuple[Any, Any, Any]:
    """t, qpos, qvel of the simulated robot, every k-th control tick (k = control rate / reference rate)."""
    a = res.arrays
    k = max(1, round(1.0 / (float(case["reference_rate"]) * case["control_period"])))
    return a["t"][::k], a["qpos"][::k], a["qvel"][::k]


#: how a case is computed: ``reference_mode`` (task reference) or else the task -> runner
RUNNERS = {"simulate": _simulate, "plan": _plan, "closed-loop": _simulate, "kinematic": _plan}
#: reference mode -> the motion of the runner's output
MOTIONS = {"closed-loop": _sim_motion, "kinematic": _ik_motion}


def _motion(case: dict[str, Any], cfg: Any, source: Any, extra: dict[str, Any]) -> dict[str, Any]:
    """The whole-body motion at ``reference_rate`` Hz (:data:`MOTIONS`); ``extra`` goes into its meta."""
    from gaitshift.wholebody.joints import coordinate_names

    t, qpos, qvel = MOTIONS[case["reference_mode"]](case, cfg, source)
    qn, vn = coordinate_names(cfg.model())
    keys = ("robot", "scenario", "gait", "speed", "yaw_rate", "reference_mode", "case_hash")
    meta = {k: case[k] for k in keys} | {"robot_name": cfg.name, "qpos_names": qn, "qvel_names": vn} | extra
    return {"t": np.asarray(t), "qpos": np.asarray(qpos), "qvel": np.asarray(qvel), "meta": json.dumps(meta)}


def run_case(case: dict[str, Any], scenario: Any) -> dict[str, Any]:
    """Run one case (module docstring) in this process and return its row and motion."""
    from gaitshift.api import with_robot
    from gaitshift.robots import load_robot

    wall0, cpu0 = time.perf_counter(), time.process_time()
    row: dict[str, Any] = dict.fromkeys(METRICS) | dict(case)
    motion = None
    try:
        sc, robot = with_robot(edited_scenario(scenario, case), case["robot"])
        cfg = load_robot(robot)
        metrics, source = RUNNERS[case["reference_mode"] or case["task"]](sc, cfg, case)
        row.update(metrics)
        if case["task"] == "reference":
            motion = _motion(case, cfg, source, {"gaits": row["plan_gaits"], "duration": row["plan_duration"]})
    except GaitshiftError as exc:
        row["error"] = " ".join(str(exc).split())
    row["wall_time"] = time.perf_counter() - wall0
    row["cpu_time"] = time.process_time() - cpu0
    row["gaitshift_version"] = gaitshift.__version__
    return {"row": row, "motion": motion}
