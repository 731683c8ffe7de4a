"""Summary metrics of a closed-loop run (the table of ``gaitshift simulate``).

* ``fell``, ``fall_time`` and ``steps_completed`` (planned touchdowns reached before the fall);
* CoM tracking RMS per gait ("walk", "run", "stand", see :func:`step_labels`) and axis, m;
* flight: per planned flight phase, the planned duration and the longest interval with both soles
  measured off the floor that overlaps it (+/- 0.1 s); ``flight_ratio`` is the mean achieved/planned
  over the constant-speed running steps (stride equal to the plan's largest stride), or over all
  running steps when none is constant;
* speed error two steps after each command: for every change of ``command_vel`` (online plans), the
  mean measured forward CoM speed over the step from the 3rd to the 4th take-off after it (the online
  generator reaches a command at the take-off of the second step after the one already planned),
  minus the command; the plan's own mean speed over the same window is reported alongside;
* ``mean_forward_speed_max`` ("max step speed"): the largest mean forward CoM speed over one step
  (between consecutive planned touchdowns reached), forward being the plan's heading at each tick
  (:func:`forward_distance`), so that a turning run reads its speed and not its world-x part;
* peak |tau| / tau_max over all joints and ticks;
* ``legs_touch_time`` and ``feet_overlap_time``: how long the two legs touched each other, s
  (:mod:`gaitshift.sim.leg_clearance`);
* ``fall_cause``: crossing, slip, estimate, torque or reach (:mod:`gaitshift.sim.fall_cause`), None
  without a fall;
* real-time factor = simulated time / wall time.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from gaitshift.common.runs import true_runs
from gaitshift.sim.fall_cause import fall_cause
from gaitshift.sim.result import SimResult
from gaitshift.sim.tracking import heading_errors, stride_speed_errors
from gaitshift.trajectory.contract import FLIGHT, Trajectory

GAITS = ("stand", "walk", "run")


def step_labels(traj: Trajectory) -> np.ndarray:
    """Gait label per plan sample, (N,) object: the plan's ``gait`` (0 "stand", 1 "walk", 2 "run")."""
    labels: np.ndarray = np.asarray(GAITS, dtype=object)[traj.gait]
    return labels


def touchdowns(traj: Trajectory) -> np.ndarray:
    """Sample indices of the plan's touchdowns (a foot's contact flag turns on), increasing."""
    c = traj.contact
    return np.flatnonzero(np.any(~c[:-1] & c[1:], axis=1)) + 1


def _com_tracking(a: dict[str, np.ndarray], labels: np.ndarray) -> dict[str, Any]:
    """RMS per gait and axis of the CoM error against the tracked reference and the unshifted plan."""
    err = a["com_pos"] - a["com_ref"]
    rms = {g: np.sqrt(np.mean(err[labels == g] ** 2, axis=0)).tolist() for g in GAITS if np.any(labels == g)}
    # against the original plan (without the capture-point shift of the reference)
    err_plan = a["com_pos"] - (a["com_ref"] - a["com_shift"])
    return {
        "com_rms": rms,
        "com_rms_plan": {
            g: np.sqrt(np.mean(err_plan[labels == g] ** 2, axis=0)).tolist() for g in GAITS if np.any(labels == g)
        },
        "max_shift": float(np.max(np.abs(a["com_shift"][:, :2]))),
        "com_max_abs": np.max(np.abs(err), axis=0).tolist(),
    }


def _period(result: SimResult) -> float:
    """The run's control period, s: from its meta, else the median step of its times (plan time
    stalls while the robot settles, so a difference of two times can be 0)."""
    period, t = result.meta.get("control_period"), result.arrays["t"]
    return float(period) if period else (float(np.median(np.diff(t))) if len(t) > 1 else 0.0)


def _flight(a: dict[str, np.ndarray], traj: Trajectory, land: np.ndarray, t_end: float, dt: float) -> dict[str, Any]:
    """Planned vs achieved flight durations (see module docstring), ``dt`` the control period (s); {}
    when no flight was reached."""
    tt = a["t"]
    air_runs = [(tt[s], tt[e - 1] + dt) for s, e in true_runs(~np.any(a["contact"], axis=1))]
    fs = traj.footsteps
    stride = np.linalg.norm(np.diff(fs[:, :2], axis=0), axis=1) if len(fs) > 1 else np.zeros(0)
    per = []
    for s, e in true_runs(traj.phase == FLIGHT):
        t0, t1 = traj.t[s], traj.t[min(e, len(traj) - 1)]
        if t1 > t_end:
            break
        best = 0.0
        for a0, a1 in air_runs:
            if a1 >= t0 - 0.1 and a0 <= t1 + 0.1:
                best = max(best, a1 - a0)
        # stride of the step that lands after this flight
        k = int(np.sum(traj.t[land] <= t1))
        st = float(stride[k]) if k < len(stride) else 0.0
        per.append((t1 - t0, best, st))
    if not per:
        return {}
    arr = np.array(per)
    const = np.isclose(arr[:, 2], arr[:, 2].max(), atol=0.02)
    use = arr[const] if np.any(const) else arr
    return {
        "flight_planned_mean": float(use[:, 0].mean()),
        "flight_achieved_mean": float(use[:, 1].mean()),
        "flight_ratio": float(use[:, 1].mean() / use[:, 0].mean()),
        "flight_all": arr.tolist(),
    }


def _speed_errors(a: dict[str, np.ndarray], traj: Trajectory, t_end: float) -> list[list[float]]:
    """Per command change of an online VHIP plan: [t, command, measured, measured - command, planned]
    (see module docstring; other plans report the stride metrics of :mod:`gaitshift.sim.tracking`)."""
    cmd = traj.command_vel
    errs: list[list[float]] = []
    if traj.meta.get("planner") != "vhip" or not np.any(np.isfinite(cmd)):
        return errs
    tt = a["t"]
    valid = np.isfinite(cmd[:, 0])
    change = np.flatnonzero(valid[1:] & (~valid[:-1] | (np.abs(np.diff(cmd[:, 0])) > 1e-9))) + 1
    if valid[0]:
        change = np.concatenate([[0], change])
    air = ~np.any(traj.contact, axis=1)
    takeoff = np.flatnonzero(~air[:-1] & air[1:]) + 1
    for ic in change:
        to = traj.t[takeoff[takeoff > ic]]
        # the generator reaches a command at the 3rd take-off after it (to_{k+2}); measure the mean
        # forward speed over the step that follows (to_{k+2}, to_{k+3})
        if len(to) < 4 or to[3] > t_end:
            continue
        sel = (tt >= to[2]) & (tt < to[3])
        psel = (traj.t >= to[2]) & (traj.t < to[3])
        if np.any(sel):
            v = float(np.mean(a["com_vel"][sel, 0]))
            vp = float(np.mean(traj.com_vel[psel, 0]))
            errs.append([float(traj.t[ic]), float(cmd[ic, 0]), v, v - float(cmd[ic, 0]), vp])
    return errs


def forward_distance(a: dict[str, np.ndarray], traj: Trajectory) -> np.ndarray:
    """Distance travelled forward by the measured CoM in the plan's heading frame, from the first tick, m
    (one per tick): the sum over ticks of the horizontal displacement along the plan's heading at the
    middle of the tick (mean of the headings at its two ends)."""
    psi = traj.heading[a["plan_index"]]
    mid = psi[:-1] + 0.5 * ((np.diff(psi) + math.pi) % (2.0 * math.pi) - math.pi)
    dp = np.diff(a["com_pos"][:, :2], axis=0)
    ahead = dp[:, 0] * np.cos(mid) + dp[:, 1] * np.sin(mid)
    return np.concatenate([[0.0], np.cumsum(ahead)])


def _step_mean_speed(a: dict[str, np.ndarray], traj: Trajectory, land: np.ndarray, t_end: float) -> np.ndarray:
    """Mean forward CoM speed in the heading frame between consecutive planned touchdowns reached, m/s
    (:func:`forward_distance`: a turn at a constant speed reads that speed, not its world-x part)."""
    tl = traj.t[land]
    tl = tl[tl <= t_end]
    if len(tl) < 2:
        return np.zeros(0)
    s = np.interp(tl, a["t"], forward_distance(a, traj))
    speed: np.ndarray = np.diff(s) / np.diff(tl)
    return speed


def summarize(result: SimResult, traj: Trajectory, torque_limit: np.ndarray) -> dict[str, Any]:
    """The metrics of ``result``, a run of the plan ``traj``, with the motors' ``torque_limit`` (nu,)
    N m (see module docstring)."""
    a = result.arrays
    land = touchdowns(traj)
    out: dict[str, Any] = {
        "fell": bool(result.fell),
        "fall_time": float(result.fall_time) if result.fell else None,
        "fall_reason": result.fall_reason,
        "fall_cause": None,
        "steps_planned": len(land),
        "steps_completed": 0,
        "peak_torque_fraction": 0.0,
        "real_time_factor": float(result.meta.get("real_time_factor", 0.0)),
        "qp_failures": 0,
        "legs_touch_time": 0.0,
        "feet_overlap_time": 0.0,
    }
    if len(a["t"]) == 0:  # fell before the first control tick (t = 0)
        return out
    out.update(_com_tracking(a, step_labels(traj)[a["plan_index"]]))
    # steps completed: planned touchdowns before the end of the run
    t_end = float(a["t"][-1])
    out["steps_planned"] = len(land)
    out["steps_completed"] = int(np.sum(traj.t[land] <= t_end))
    dt = _period(result)
    if result.fell:
        out["fall_cause"] = fall_cause(a, float(result.fall_time), torque_limit, dt)
    out.update(_flight(a, traj, land, t_end, dt))
    errs = _speed_errors(a, traj, t_end)
    out["speed_errors"] = errs
    out["speed_error_max"] = float(max((abs(e[3]) for e in errs), default=math.nan))
    qw = a["qpos"][:, 3:7]  # pelvis quaternion (w, x, y, z): tilt = angle between its z axis and world z
    r22 = 1.0 - 2.0 * (qw[:, 1] ** 2 + qw[:, 2] ** 2)
    out["max_pelvis_tilt_deg"] = float(np.degrees(np.max(np.arccos(np.clip(r22, -1.0, 1.0)))))
    out["peak_torque_fraction"] = float(np.max(np.abs(a["tau"]) / torque_limit))
    out["real_time_factor"] = float(result.meta["real_time_factor"])
    out["qp_failures"] = int(np.sum(~a["qp_ok"]))
    for key in ("legs_touch", "feet_overlap"):  # logs older than these keys: 0
        out[f"{key}_time"] = float(np.sum(a[key]) * dt) if key in a else 0.0
    # top speed held: mean forward CoM speed (heading frame) between consecutive planned touchdowns reached
    out["mean_forward_speed_max"] = float(np.max(_step_mean_speed(a, traj, land, t_end), initial=0.0))
    out.update(stride_speed_errors(a, traj))
    out.update(heading_errors(a, traj))
    return out


def _state_rows(metrics: dict[str, Any]) -> list[tuple[str, str]]:
    """What the controller acted on, and how well the estimate tracked the truth (when it ran)."""
    if "state_source" not in metrics:
        return []
    rows = [("controller's state", str(metrics["state_source"]))]
    est = metrics.get("estimation") or {}
    if "contact_accuracy" in est:
        acc, vel, tilt = 100 * est["contact_accuracy"], est["base_vel_rmse"], est["tilt_rmse"]
        rows.append(("estimate contact/vel/tilt", f"{acc:.1f} % / {vel:.4f} m/s / {tilt:.4f} rad RMS"))
    return rows


def format_metrics(metrics: dict[str, Any]) -> str:
    """The summary as a two-column text table."""
    rows = [("fell", "yes" if metrics["fell"] else "no")]
    if metrics["fell"]:
        cause = metrics.get("fall_cause")
        why = metrics.get("fall_reason", "") + (f"; cause: {cause}" if cause else "")
        rows.append(("fall time (s)", f"{metrics.get('fall_time') or 0.0:.3f}  ({why})"))
    rows.append(("steps completed", f"{metrics.get('steps_completed', 0)} / {metrics.get('steps_planned', 0)}"))
    for g, r in metrics.get("com_rms", {}).items():
        rows.append((f"CoM RMS {g} x/y/z (cm)", " / ".join(f"{100 * v:.2f}" for v in r)))
    for g, r in metrics.get("com_rms_plan", {}).items():
        if g != "stand":
            rows.append((f"  vs original plan {g} (cm)", " / ".join(f"{100 * v:.2f}" for v in r)))
    if "flight_ratio" in metrics:
        rows.append(
            (
                "flight planned / achieved (s)",
                f"{metrics['flight_planned_mean']:.3f} / {metrics['flight_achieved_mean']:.3f} "
                f"(ratio {metrics['flight_ratio']:.2f})",
            )
        )
    for t, c, v, e, vp in metrics.get("speed_errors", []):
        rows.append((f"speed, command at t={t:.2f}s", f"cmd {c:.2f}  plan {vp:.2f}  meas {v:.2f}  err {e:+.3f} m/s"))
    if "max_pelvis_tilt_deg" in metrics:
        rows.append(("max pelvis tilt (deg)", f"{metrics['max_pelvis_tilt_deg']:.1f}"))
    rows.append(("peak torque / limit", f"{metrics.get('peak_torque_fraction', 0.0):.2f}"))
    rows.append(("max step speed (m/s)", f"{metrics.get('mean_forward_speed_max', 0):.2f}"))
    if math.isfinite(metrics.get("stride_speed_error_max") or math.nan):
        rows.append(
            (
                "stride speed error max / RMS (m/s)",
                f"{metrics['stride_speed_error_max']:.3f} / {metrics['stride_speed_error_rms']:.3f} "
                f"({len(metrics['stride_speed_errors'])} steady strides)",
            )
        )
    if "heading_error_max" in metrics:
        rows.append(
            (
                "heading error max / RMS (rad)",
                f"{metrics['heading_error_max']:.3f} / {metrics['heading_error_rms']:.3f}",
            )
        )
    rows.append(("QP failures", str(metrics.get("qp_failures", 0))))
    touch, overlap = metrics.get("legs_touch_time", 0.0), metrics.get("feet_overlap_time", 0.0)
    rows.append(("legs touch / feet overlap (s)", f"{touch:.3f} / {overlap:.3f}"))
    rows.append(("real-time factor", f"{metrics.get('real_time_factor', 0.0):.2f}"))
    rows += _state_rows(metrics)
    w = max(len(r[0]) for r in rows)
    return "\n".join(f"{k.ljust(w)}  {v}" for k, v in rows)
