"""Closed loop: a planned :class:`~gaitshift.trajectory.Trajectory` executed on the simulated G1.

Every control tick (= physics step, 2 ms by default):

1. read the state (``mj_forward`` + ``mj_subtreeVel``): CoM, momentum, foot contacts;
2. update the foot state machine (contact schedule of the plan, with early/late touchdown from the
   measured MuJoCo contacts, see :class:`FootScheduler`);
3. build the tick reference from the plan (CoM position, velocity, acceleration; swing-foot path
   shifted by the step-level capture-point correction, see :func:`capture_point_offset`);
4. solve the whole-body QP (:mod:`gaitshift.sim.controller`) and apply the torques;
5. log, and stop at a fall (pelvis below 60 % of its initial height, or any non-sole geom touching
   the floor).

Step-level feedback, TV-LIPM plans (capture point): while a foot swings (until ``freeze_u`` of its
swing) its target is moved by ``k_cp (xi - xi_ref)``, with ``xi = c + cd / omega`` the measured
divergent component of motion and ``xi_ref`` that of the (shifted) plan, omega = sqrt(g / h),
clipped to ``max_step_adjust``. When the foot lands, the whole remaining plan (CoM reference and
later footholds) is translated by that correction, blended in over ``shift_time``: the plan is
re-anchored on where the robot actually stands, as the LIPM is translation invariant.

Step-level feedback, online VHIP plans: :class:`OnlineReplanner` re-plans every next step from the
measured CoM with the paper-003 generator itself (the capture-point shift is then off).
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from ..errors import InputError
from ..io import atomic_path
from ..swing import min_jerk
from ..trajectory import FLIGHT, Trajectory
from .controller import Gains, TickReference, WholeBodyController, _rot_z, rotation_error
from .plant import Plant, build_plant, standing_qpos

FALL_HEIGHT_FRACTION = 0.6


@dataclass(frozen=True)
class Push:
    """A lateral push: a horizontal force applied to the pelvis for ``duration`` s from ``t``.

    ``impulse`` (N s) along ``direction`` (unit (2,) in the ground plane)."""

    t: float
    impulse: float
    duration: float = 0.1
    direction: tuple[float, float] = (0.0, 1.0)


@dataclass(frozen=True)
class SimOptions:
    """Options of a closed-loop run."""

    control_period: float = 0.002
    gains: Gains = field(default_factory=Gains)
    touchdown_ramp: float = 0.03        # s: normal-force cap ramp after touchdown
    liftoff_ramp: float = 0.01          # s: unloading before a planned lift-off
    early_touchdown_u: float = 0.6      # swing progress after which a contact counts as touchdown
    late_descent_speed: float = 0.3     # m/s: how fast a late foot keeps going down
    capture_gain: float = 1.0
    freeze_u: float = 0.7               # swing progress after which the foothold correction is frozen
    shift_time: float = 0.1             # s: time constant of the plan shift after a corrected touchdown
    flight_clearance: float = 0.04      # m: extra parabolic lift of swings that span a flight
    max_step_adjust: float = 0.10       # m
    settle: float = 0.0                 # s of standing before the plan starts
    pushes: tuple[Push, ...] = ()
    video: str | None = None
    video_fps: int = 25
    viewer: bool = False


@dataclass
class SimResult:
    """Logged arrays (per control tick) and the summary.

    File keys (``save``): the arrays (``t``, ``qpos``, ``qvel``, ``tau``, ``com_pos``, ``com_ref`` (the
    reference tracked: plan + capture-point shift), ``com_vel``, ``com_vel_ref``, ``contact`` (measured),
    ``contact_ref``, ``stance`` (controller), ``grf`` (N, 2, 3) measured, ``grf_ref`` (QP), ``foot_pos``,
    ``foot_ref``, ``angmom``, ``com_shift``, ``plan_index``, ``qp_ok``, ``push_force``), ``fell``,
    ``fall_time`` (s; -1 when the robot did not fall) and ``meta`` (strict JSON, with the metrics).
    """

    arrays: dict[str, np.ndarray]
    fell: bool
    fall_time: float
    fall_reason: str
    meta: dict[str, Any]
    metrics: dict[str, Any]

    def save(self, path: str | Path) -> Path:
        path = Path(path)
        if path.suffix.lower() != ".npz":
            raise InputError("out", str(path), "a file ending in .npz")
        meta = dict(self.meta, metrics=self.metrics, fall_reason=self.fall_reason)
        with atomic_path(path) as tmp:
            with open(tmp, "wb") as fh:
                np.savez_compressed(fh, **self.arrays, fell=np.array(self.fell),
                                    fall_time=np.array(self.fall_time if self.fell else -1.0),
                                    meta=np.array(json.dumps(finite_json(meta), allow_nan=False)))
        return path


def finite_json(obj: Any) -> Any:
    """``obj`` with every non-finite float replaced by None (strict JSON, no NaN in output files)."""
    if isinstance(obj, dict):
        return {str(k): finite_json(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [finite_json(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return finite_json(obj.tolist())
    if isinstance(obj, (float, np.floating)):
        return float(obj) if math.isfinite(obj) else None
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    return obj


# ============================================================================ plan preprocessing
def _plan_arrays(traj: Trajectory) -> dict[str, np.ndarray]:
    """Per-sample references from the plan: foot velocities/accelerations by central differences,
    foot yaws, lift-off and touchdown times of each foot."""
    dt = traj.dt
    fp = traj.foot_pos
    fv = np.gradient(fp, dt, axis=0)
    fa = np.gradient(fv, dt, axis=0)
    fs = traj.footsteps
    side = traj.footstep_side
    yaw = np.zeros((len(traj), 2))
    for s in (0, 1):
        idx = np.flatnonzero(side == s)
        d = np.linalg.norm(fp[:, s, None, :2] - fs[None, idx, :2], axis=-1)
        yaw[:, s] = fs[idx[np.argmin(d, axis=1)], 3]
    c = traj.contact
    t = traj.t
    lift = [t[1:][c[:-1, s] & ~c[1:, s]] for s in (0, 1)]
    land = [t[1:][~c[:-1, s] & c[1:, s]] for s in (0, 1)]
    return {"foot_vel": fv, "foot_acc": fa, "yaw": yaw, "lift": lift, "land": land}


def step_labels(traj: Trajectory) -> np.ndarray:
    """Gait label per plan sample: "walk"/"run" for the step being taken, "stand" before the first
    lift-off and after the last touchdown. Step j spans from its lift-off to its touchdown plus the
    following support (DS or SS-before-flight)."""
    c = traj.contact
    lift = np.flatnonzero(np.any(c[:-1] & ~c[1:], axis=1)) + 1
    default = "run" if traj.meta.get("planner") == "vhip" else "walk"
    gaits = list(traj.meta.get("step_gait", []))
    labels = np.full(len(traj), "stand", dtype=object)
    if len(lift) == 0:
        return labels
    land_any = np.flatnonzero(np.any(~c[:-1] & c[1:], axis=1)) + 1
    end = land_any[-1] if len(land_any) else len(traj) - 1
    for j, i0 in enumerate(lift):
        i1 = lift[j + 1] if j + 1 < len(lift) else end
        g = gaits[j] if j < len(gaits) else (gaits[-1] if gaits else default)
        labels[i0:i1] = g
    return labels


# ============================================================================ initial pose
def initial_qpos(plant: Plant, com: np.ndarray, feet: np.ndarray, yaws: np.ndarray, iters: int = 200) -> np.ndarray:
    """Standing configuration with sole centres at ``feet`` (2, 3), flat with yaw ``yaws`` (2,),
    and the CoM at ``com`` (3,): damped Gauss-Newton on these 15 equations (posture regularised).

    Raises:
        InputError: the pose is out of reach (residual above 2 mm).
    """
    m = plant.model
    d = mujoco.MjData(m)
    best = None
    for bend in np.linspace(0.1, 0.9, 17):  # initial guess: the leg flexion giving the CoM height
        qb = standing_qpos(plant, bend=float(bend))
        d.qpos[:] = qb
        mujoco.mj_kinematics(m, d)
        mujoco.mj_comPos(m, d)
        gap = abs(d.subtree_com[0][2] - com[2])
        if best is None or gap < best[0]:
            best = (gap, qb, d.subtree_com[0].copy())
    q = best[1]
    q[0] += com[0] - best[2][0]
    q[1] += com[1] - best[2][1]
    q_post = q.copy()
    jp, jr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
    err = np.inf
    for _ in range(iters):
        d.qpos[:] = q
        mujoco.mj_kinematics(m, d)
        mujoco.mj_comPos(m, d)
        rows, res = [], []
        for s in (0, 1):
            c, R = plant.sole_frame(d, s)
            mujoco.mj_jac(m, d, jp, jr, c, plant.soles[s].body)
            rows += [jp.copy(), jr.copy()]
            res += [feet[s] - c, rotation_error(_rot_z(yaws[s]), R)]
        mujoco.mj_jacSubtreeCom(m, d, jp, 0)
        rows.append(jp.copy())
        res.append(com - d.subtree_com[0])
        mujoco.mj_jacBody(m, d, jp, jr, plant.pelvis_body)
        rows.append(jr.copy())
        res.append(rotation_error(_rot_z(float(np.mean(yaws))), d.xmat[plant.pelvis_body].reshape(3, 3)))
        J = np.vstack(rows)
        r = np.concatenate(res)
        err = float(np.max(np.abs(r[:15])))
        if err < 1e-7:
            break
        dq_post = np.zeros(m.nv)
        dq_post[6:] = q_post[7:] - q[7:]
        A = J.T @ J + 1e-4 * np.eye(m.nv)
        dq = np.linalg.solve(A, J.T @ r + 1e-5 * dq_post)
        mujoco.mj_integratePos(m, q, dq, 1.0)
    if err > 2e-3:
        raise InputError("scenario", "initial stance", f"a reachable standing pose (IK residual {err * 1e3:.1f} mm)")
    return q


# ============================================================================ foot scheduling
class FootScheduler:
    """Stance/swing state of each foot from the plan, corrected by measured contacts.

    * Early touchdown: a swinging foot that touches the floor after ``early_touchdown_u`` of its swing
      becomes a stance foot at once.
    * Late touchdown: a foot whose planned swing is over but which has not touched keeps swinging,
      descending at ``late_descent_speed`` until it touches.
    * The normal-force cap of a foot ramps from 0 to full over ``touchdown_ramp`` after its touchdown
      (impact absorption) and from full to 0 over the last ``liftoff_ramp`` of its planned stance.
    """

    def __init__(self, traj: Trajectory, pre: dict[str, Any], opts: SimOptions, weight: float) -> None:
        self.traj = traj
        self.pre = pre
        self.opts = opts
        self.full = 4.0 * weight
        self.stance = traj.contact[0].copy()
        self.t_touch = np.full(2, -1.0)
        self.swing_start = np.zeros(2)
        self.swing_end = np.zeros(2)
        self.offset = np.zeros((2, 3))
        self.swing_flight = np.zeros(2, bool)
        self.lift_at = np.array([self.next_time(pre["lift"][k], 0.0) for k in (0, 1)])

    def next_time(self, times: np.ndarray, t: float) -> float:
        i = np.searchsorted(times, t - 1e-9)
        return float(times[i]) if i < len(times) else math.inf

    def update(self, t: float, i: int, touching: np.ndarray) -> None:
        planned = self.traj.contact[i]
        for s in (0, 1):
            if self.stance[s]:
                if t >= self.lift_at[s] - 1e-9 and t >= self.t_touch[s] + self.opts.touchdown_ramp:
                    self.stance[s] = False
                    self.swing_start[s] = t
                    self.swing_end[s] = self.next_time(self.pre["land"][s], t)
                    j0 = int(round(t / self.traj.dt))
                    j1 = int(round(min(self.swing_end[s], float(self.traj.t[-1])) / self.traj.dt))
                    self.swing_flight[s] = bool(np.any(self.traj.phase[j0:j1 + 1] == FLIGHT))
            else:
                dur = max(self.swing_end[s] - self.swing_start[s], 1e-6)
                u = (t - self.swing_start[s]) / dur
                if touching[s] and (planned[s] or u >= self.opts.early_touchdown_u):
                    self.stance[s] = True
                    self.t_touch[s] = t
                    # the stance lasts until the plan's lift-off that follows the planned touchdown
                    self.lift_at[s] = self.next_time(self.pre["lift"][s], max(t, self.swing_end[s]))

    def force_caps(self, t: float) -> np.ndarray:
        caps = np.zeros(2)
        for s in (0, 1):
            if not self.stance[s]:
                continue
            up = 1.0 if self.t_touch[s] < 0 else min(1.0, (t - self.t_touch[s]) / self.opts.touchdown_ramp)
            t_lift = self.lift_at[s]
            down = min(1.0, max(0.0, (t_lift - t) / self.opts.liftoff_ramp))
            caps[s] = self.full * min(up, down) + 1e-3
        return caps


def capture_point_offset(com, com_vel, com_ref, vel_ref, omega, gain, limit) -> np.ndarray:
    """Foothold correction (3,) = gain (xi - xi_ref), horizontal, clipped to ``limit`` per axis (m)."""
    xi = com[:2] + com_vel[:2] / omega
    xi_ref = com_ref[:2] + vel_ref[:2] / omega
    out = np.zeros(3)
    out[:2] = np.clip(gain * (xi - xi_ref), -limit, limit)
    return out


# ============================================================================ the loop
def simulate(traj: Trajectory, opts: SimOptions | None = None, plant: Plant | None = None,
             replanner: "OnlineReplanner | None" = None) -> SimResult:
    """Run ``traj`` closed-loop on the G1 and return the logged result (see module docstring).

    With a ``replanner`` (online VHIP plans), the plan is regenerated from the measured CoM at every
    planning instant and the capture-point shift is not used (the generator's footholds do that job).
    """
    opts = opts or SimOptions()
    if replanner is not None:
        traj = replanner.trajectory
        opts = replace(opts, capture_gain=0.0)
    plant = plant or build_plant(opts.control_period)
    m = plant.model
    d = mujoco.MjData(m)
    dt = plant.dt
    pre = _plan_arrays(traj)
    q0 = initial_qpos(plant, traj.com_pos[0], traj.foot_pos[0], pre["yaw"][0])
    d.qpos[:] = q0
    mujoco.mj_forward(m, d)
    ctrl = WholeBodyController(plant, q0, opts.gains)
    sched = FootScheduler(traj, pre, opts, plant.mass * 9.81)
    height = float(traj.meta.get("height", traj.com_pos[0, 2]))
    omega = math.sqrt(traj.gravity / height)
    pelvis0 = float(q0[2])
    sole_geoms = set(plant.soles[0].geoms) | set(plant.soles[1].geoms)
    foot_geom_side = {g: s for s in (0, 1) for g in plant.soles[s].geoms}

    t_plan_end = float(traj.t[-1])
    n_ticks = int(round((t_plan_end + opts.settle + (2.0 if replanner else 0.0)) / dt)) + 1
    nq, nv, nu = m.nq, m.nv, m.nu
    log = {
        "t": np.zeros(n_ticks), "qpos": np.zeros((n_ticks, nq)), "qvel": np.zeros((n_ticks, nv)),
        "tau": np.zeros((n_ticks, nu)), "com_pos": np.zeros((n_ticks, 3)), "com_ref": np.zeros((n_ticks, 3)),
        "com_vel": np.zeros((n_ticks, 3)), "com_vel_ref": np.zeros((n_ticks, 3)),
        "contact": np.zeros((n_ticks, 2), bool), "contact_ref": np.zeros((n_ticks, 2), bool),
        "stance": np.zeros((n_ticks, 2), bool), "grf": np.zeros((n_ticks, 2, 3)),
        "grf_ref": np.zeros((n_ticks, 2, 3)), "foot_pos": np.zeros((n_ticks, 2, 3)),
        "foot_ref": np.zeros((n_ticks, 2, 3)), "angmom": np.zeros((n_ticks, 3)),
        "plan_index": np.zeros(n_ticks, np.int64), "com_shift": np.zeros((n_ticks, 3)), "qp_ok": np.zeros(n_ticks, bool),
    }
    push_force = np.zeros((n_ticks, 3))
    for p in opts.pushes:
        i0 = int(round((p.t + opts.settle) / dt))
        i1 = i0 + max(1, int(round(p.duration / dt)))
        dirn = np.array([*p.direction, 0.0])
        dirn /= max(np.linalg.norm(dirn), 1e-12)
        push_force[i0:min(i1, n_ticks)] = dirn * p.impulse / ((i1 - i0) * dt)
    log["push_force"] = push_force

    renderer, frames, viewer = None, [], None
    if opts.video:
        renderer = _make_renderer(m)
    if opts.viewer:
        viewer = _open_viewer(m, d)
    next_frame = 0.0
    fell, fall_time, reason = False, math.nan, ""
    wall0 = time.perf_counter()
    render_wall = 0.0
    shift = np.zeros(3)
    shift_target = np.zeros(3)
    cf = np.zeros(6)
    n_done = n_ticks
    for k in range(n_ticks):
        t = k * dt
        tp = max(0.0, t - opts.settle)
        if tp > float(traj.t[-1]) + 0.5 * dt:
            n_done = k
            break
        i = min(int(round(tp / traj.dt)), len(traj) - 1)
        mujoco.mj_forward(m, d)
        mujoco.mj_subtreeVel(m, d)
        touching = np.zeros(2, bool)
        grf = np.zeros((2, 3))
        bad = None
        for ci in range(d.ncon):
            con = d.contact[ci]
            g1, g2 = con.geom[0], con.geom[1]
            if plant.floor_geom not in (g1, g2):
                continue
            other = g2 if g1 == plant.floor_geom else g1
            if other not in sole_geoms:
                bad = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, m.geom_bodyid[other])
                continue
            s = foot_geom_side[other]
            touching[s] = True
            mujoco.mj_contactForce(m, d, ci, cf)
            fw = con.frame.reshape(3, 3).T @ cf[:3]
            grf[s] += fw if other == g2 else -fw
        com = d.subtree_com[0].copy()
        if bad is not None or d.qpos[2] < FALL_HEIGHT_FRACTION * pelvis0:
            fell, fall_time = True, tp
            reason = f"{bad} touched the floor" if bad else "pelvis below 60% of its initial height"
            n_done = k
            break
        if replanner is not None:
            new = replanner.maybe_replan(tp, com, d.subtree_linvel[0])
            if new is not None:
                traj = new
                pre = _plan_arrays(traj)
                sched.traj, sched.pre = traj, pre
                i = min(int(round(tp / traj.dt)), len(traj) - 1)
        was_swing = ~sched.stance.copy()
        if tp > 0 or opts.settle == 0:
            sched.update(tp, i, touching)
        # step-level capture-point feedback: a foot that has just landed moves the whole remaining
        # plan by its foothold correction (blended in over shift_time); the swinging foot's
        # correction is recomputed every tick until ``freeze_u`` of its swing
        for s in (0, 1):
            if was_swing[s] and sched.stance[s]:
                shift_target += sched.offset[s]
                sched.offset[s] = 0.0
        shift += (shift_target - shift) * min(1.0, dt / opts.shift_time)
        com_ref = traj.com_pos[i] + shift
        if opts.capture_gain > 0:
            for s in (0, 1):
                if sched.stance[s]:
                    continue
                u = (tp - sched.swing_start[s]) / max(sched.swing_end[s] - sched.swing_start[s], 1e-6)
                if u < opts.freeze_u:
                    sched.offset[s] = capture_point_offset(com, d.subtree_linvel[0], traj.com_pos[i] + shift_target,
                                                           traj.com_vel[i], omega, opts.capture_gain,
                                                           opts.max_step_adjust)
        foot_ref = traj.foot_pos[i].copy()
        foot_vel = pre["foot_vel"][i].copy()
        foot_acc = pre["foot_acc"][i].copy()
        for s in (0, 1):
            if sched.stance[s]:
                continue
            dur = max(sched.swing_end[s] - sched.swing_start[s], 1e-6)
            u = (tp - sched.swing_start[s]) / dur
            foot_ref[s] += shift + sched.offset[s] * min_jerk(np.array(u))
            if sched.swing_flight[s] and 0.0 <= u <= 1.0:
                # running swing: lift off and set down with a vertical speed (parabolic bump)
                hb = opts.flight_clearance
                foot_ref[s, 2] += 4.0 * hb * u * (1.0 - u)
                foot_vel[s, 2] += 4.0 * hb * (1.0 - 2.0 * u) / dur
                foot_acc[s, 2] += -8.0 * hb / dur**2
            if traj.contact[i, s] and u > 1.0:  # late touchdown: keep descending
                late = tp - sched.swing_end[s]
                foot_ref[s, 2] -= opts.late_descent_speed * late
                foot_vel[s] = [0.0, 0.0, -opts.late_descent_speed]
                foot_acc[s] = 0.0
        ref = TickReference(
            com_pos=com_ref, com_vel=traj.com_vel[i], com_acc=traj.com_acc[i],
            stance=sched.stance.copy(), fz_max=sched.force_caps(tp), foot_pos=foot_ref,
            foot_vel=foot_vel, foot_acc=foot_acc, yaw=pre["yaw"][i], torso_yaw=float(pre["yaw"][i].mean()))
        tau, info = ctrl.compute(d, ref)
        d.ctrl[:] = tau
        d.xfrc_applied[plant.pelvis_body, :3] = push_force[k]
        log["t"][k] = tp
        log["qpos"][k] = d.qpos
        log["qvel"][k] = d.qvel
        log["tau"][k] = tau
        log["com_pos"][k] = com
        log["com_ref"][k] = com_ref
        log["com_shift"][k] = shift
        log["com_vel"][k] = d.subtree_linvel[0]
        log["com_vel_ref"][k] = traj.com_vel[i]
        log["contact"][k] = touching
        log["contact_ref"][k] = traj.contact[i]
        log["stance"][k] = sched.stance
        log["grf"][k] = grf
        log["grf_ref"][k] = info.forces
        log["foot_pos"][k] = [plant.sole_frame(d, s)[0] for s in (0, 1)]
        log["foot_ref"][k] = foot_ref
        log["angmom"][k] = d.subtree_angmom[0]
        log["plan_index"][k] = i
        log["qp_ok"][k] = info.ok
        if renderer is not None and t >= next_frame:
            r0 = time.perf_counter()
            frames.append(_render(renderer, d, com))
            next_frame += 1.0 / opts.video_fps
            render_wall += time.perf_counter() - r0
        if viewer is not None:
            viewer.sync()
        mujoco.mj_step(m, d)
    wall = time.perf_counter() - wall0 - render_wall  # control + physics only
    arrays = {k_: v[:n_done] for k_, v in log.items()}
    sim_time = n_done * dt
    meta = {
        "robot": "unitree_g1", "control_period": dt, "integrator": "implicitfast",
        "plan_meta": traj.meta, "wall_time_s": wall, "sim_time_s": sim_time,
        "real_time_factor": sim_time / wall if wall > 0 else math.nan,
        "torque_limit": plant.torque_limit.tolist(), "pelvis_height0": pelvis0,
        "pushes": [p.__dict__ for p in opts.pushes], "settle": opts.settle,
        "replans": replanner.replans if replanner is not None else 0,
    }
    if renderer is not None and frames:
        _write_video(opts.video, frames, opts.video_fps)
    if viewer is not None:
        viewer.close()
    from .metrics import summarize  # noqa: PLC0415

    result = SimResult(arrays=arrays, fell=fell, fall_time=fall_time, fall_reason=reason, meta=meta, metrics={})
    result.metrics = summarize(result, traj, plant)
    return result


# ============================================================================ rendering
def _make_renderer(m: mujoco.MjModel):
    try:
        return mujoco.Renderer(m, height=270, width=480)
    except Exception as exc:  # noqa: BLE001
        raise InputError("video", "render", f"an OpenGL context (set MUJOCO_GL=egl or osmesa): {exc}") from None


def _render(renderer, d: mujoco.MjData, com: np.ndarray) -> np.ndarray:
    cam = mujoco.MjvCamera()
    cam.type = mujoco.mjtCamera.mjCAMERA_FREE
    cam.lookat[:] = [com[0], com[1], 0.6]
    cam.distance = 2.8
    cam.azimuth = 120.0
    cam.elevation = -15.0
    renderer.update_scene(d, camera=cam)
    return renderer.render().copy()


def _write_video(path: str, frames: list[np.ndarray], fps: int) -> None:
    import imageio.v2 as imageio  # noqa: PLC0415

    p = Path(path)
    with atomic_path(p) as tmp:
        with imageio.get_writer(str(tmp), fps=fps, format="FFMPEG", codec="libx264",
                                macro_block_size=1) as w:
            for f in frames:
                w.append_data(f)


def _open_viewer(m, d):
    import os  # noqa: PLC0415

    if not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY"):
        raise InputError("viewer", "no display", "a graphical display (DISPLAY or WAYLAND_DISPLAY set)")
    import mujoco.viewer  # noqa: PLC0415

    return mujoco.viewer.launch_passive(m, d)


def mid_stance_pushes(traj: Trajectory, impulse: float, steps: tuple[int, ...] = (4, 8),
                      duration: float = 0.1) -> tuple[Push, ...]:
    """Lateral pushes of ``impulse`` N s centred at mid single support of the given (1-based) steps,
    alternating +y, -y. Steps beyond the plan are ignored."""
    ss = [(s, e) for s, e in _phase_runs(traj.phase == 1)]
    out = []
    for j, k in enumerate(steps):
        if 1 <= k <= len(ss):
            s, e = ss[k - 1]
            tm = 0.5 * (traj.t[s] + traj.t[min(e, len(traj) - 1)])
            out.append(Push(t=float(tm - duration / 2), impulse=float(impulse), duration=duration,
                            direction=(0.0, 1.0 if j % 2 == 0 else -1.0)))
    return tuple(out)


def _phase_runs(mask: np.ndarray) -> list[tuple[int, int]]:
    m = np.concatenate([[False], mask, [False]]).astype(np.int8)
    d = np.diff(m)
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1)))


class OnlineReplanner:
    """Closed-loop driver of the online VHIP generator (paper 003, ``gaitshift.planners.online``).

    The scenario's scripted speed commands are fed to a live :class:`OnlineGenerator` as simulated
    time passes. At every planning instant (the take-off that plans the next step) the generator
    re-plans from the **measured** CoM position and velocity (:meth:`OnlineGenerator.replan`: the
    committed footholds are kept, the next foothold is chosen again by Algorithm 1), so drift is
    corrected by footholds as the paper intends. The remainder of the run is then generated on a
    copy of the generator, which gives the loop its look-ahead (swing targets, contact schedule).
    """

    def __init__(self, scenario: Any) -> None:
        from ..planners.online import OnlineGenerator  # noqa: PLC0415

        self.sc = scenario
        self.gen = OnlineGenerator(scenario)
        self.events = sorted(((c.t, c.vx, c.vy) for c in scenario.commands), key=lambda c: c[0])
        self.stop_at = (scenario.stop_at if scenario.stop_at is not None
                        else max(c[0] for c in self.events) + 2.0)
        self._ci = 0
        self._stopped = False
        self._done: set[int] = set()
        self.replans = 0
        self._apply_due()
        self.trajectory = self._finish_copy()

    def _apply_due(self) -> None:
        g = self.gen
        while self._ci < len(self.events) and self.events[self._ci][0] <= g.t + 1e-12:
            g.command(self.events[self._ci][1], self.events[self._ci][2])
            self._ci += 1
        if not self._stopped and self.stop_at <= g.t + 1e-12:
            g.stop()
            self._stopped = True

    def _advance_to(self, index: int) -> None:
        g = self.gen
        dt = g.dt
        while g.tick_index < index and not g.finished:
            nxt = self.events[self._ci][0] if self._ci < len(self.events) else math.inf
            if not self._stopped:
                nxt = min(nxt, self.stop_at)
            target = index if not math.isfinite(nxt) else min(index, max(g.tick_index + 1, math.ceil(nxt / dt - 1e-9)))
            g.advance(target - g.tick_index)
            self._apply_due()

    def _finish_copy(self) -> Trajectory:
        import copy  # noqa: PLC0415

        from ..planners.online import run_commands  # noqa: PLC0415

        g2 = copy.deepcopy(self.gen)
        rest = [e for e in self.events[self._ci:]]
        run_commands(g2, rest, self.stop_at)
        return g2.trajectory()

    def maybe_replan(self, t: float, com: np.ndarray, com_vel: np.ndarray) -> Trajectory | None:
        """Re-plan at the planning instant that ``t`` reaches; returns the new plan or None."""
        g = self.gen
        idx = int(round(t / g.dt))
        if abs(idx * g.dt - t) > 1e-9:
            return None
        self._advance_to(idx)  # the live generator follows simulated time
        nxt = g.next_plan_index
        if nxt is None or nxt in self._done or g.tick_index != nxt or g.state != "running":
            return None
        g.replan(np.asarray(com)[:2], np.asarray(com_vel)[:2])
        self._done.add(nxt)
        self.replans += 1
        tr = self._finish_copy()
        # the sample at the re-plan joins the old plan (before) and the new one (from the measured
        # position on): its central-difference velocity mixes both, so take the new plan's forward
        # difference there (a take-off sample: flight, no CoM task uses it, only logs and figures)
        if 0 <= idx < len(tr) - 1:
            tr.com_vel[idx] = (tr.com_pos[idx + 1] - tr.com_pos[idx]) / tr.dt
        self.trajectory = tr
        return tr
