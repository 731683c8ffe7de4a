"""Why the whole-body IK (:mod:`gaitshift.wholebody.ik`) cannot follow a plan: the error it raises, naming
the time, the failing task and the cause, from the last configuration it reached.

Causes, in order: a foot out of reach (hip-to-sole distance above the robot's leg length, m), a joint
within 0.01 rad of its range (the MJCF's or the soft range the IK keeps to), a knee within
``IKSettings.knee_margin`` of straight (the straight-leg singularity); else the solver's own failure.
The task named is the one whose error is largest relative to its tolerance (CoM: ``com_tol`` m; a
sole: ``pos_tol`` m or ``rot_tol`` rad), unless a foot out of reach names its sole.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gaitshift.errors import InfeasibleError

#: a :class:`gaitshift.wholebody.ik.WholeBodyIK` (its robot, settings, configuration, joint range and
#: addresses are read; not imported here, which would be an import cycle)
WholeBodyIK = Any

TASKS = ("com", "left sole", "right sole")
SIDES = ("left", "right")


class IKInfeasibleError(InfeasibleError):
    """The robot cannot follow the plan. Attributes: ``time`` (s), ``task`` (one of ``com``,
    ``left sole``, ``right sole``, ``joint velocity``, or a plan-fit check of
    :mod:`gaitshift.wholebody.plan_fit`) and ``cause`` (text)."""

    def __init__(self, message: str, *, time: float, task: str, cause: str):
        super().__init__(message)
        self.time = time
        self.task = task
        self.cause = cause


def _causes(ik: WholeBodyIK, q: np.ndarray, reach: list[float]) -> list[tuple[int | None, str]]:
    """(task index or None, text) of every cause seen in the configuration ``q`` (nq,)."""
    leg = ik.robot.leg_length
    where = [f"{SIDES[i]} hip-to-sole distance {reach[i]:.3f} m" for i in (0, 1)]
    causes: list[tuple[int | None, str]] = [
        (i + 1, f"{SIDES[i]} foot out of reach (hip-to-sole distance {reach[i]:.3f} m > leg length {leg:.3f} m)")
        for i in (0, 1)
        if reach[i] > leg
    ]
    lo, hi = ik.joint_range[:, 0], ik.joint_range[:, 1]
    soft = f"soft range ({ik.robot.soft_joint_fraction:g} of the MJCF's) " if ik.settings.soft_limits else "range "
    qj = q[ik.qadr]
    for j in np.flatnonzero((qj - lo < 1e-2) | (hi - qj < 1e-2)):
        name = ik.robot.joint_names[j]
        causes.append((None, f"joint limit ({name} = {qj[j]:.3f} rad, {soft}[{lo[j]:.3f}, {hi[j]:.3f}])"))
    causes += [
        (
            i + 1,
            f"knee singularity ({ik.robot.knees[i]} = {q[adr]:.3f} rad, leg straight; {where[i]}, "
            f"leg length {leg:.3f} m)",
        )
        for i, adr in enumerate(ik.knee_adr)
        if abs(q[adr]) < ik.settings.knee_margin
    ]
    return causes


def diagnose(
    ik: WholeBodyIK, t: float, q: np.ndarray, feet: np.ndarray, err: np.ndarray, failure: str | None
) -> IKInfeasibleError:
    """The error of a sample at time ``t`` (s) that did not converge: ``q`` (nq,) the configuration
    reached, ``feet`` (2, 3) the sole targets (m), ``err`` (5,) the CoM, sole position (m) and sole
    orientation (rad) errors, ``failure`` the solver's failure (or None)."""
    s = ik.settings
    d = ik.conf.data
    ik.conf.update(q)
    ratios = np.array(
        [err[0] / s.com_tol, max(err[1] / s.pos_tol, err[3] / s.rot_tol), max(err[2] / s.pos_tol, err[4] / s.rot_tol)]
    )
    task = int(np.argmax(ratios))
    reach = [float(np.linalg.norm(feet[i] - d.xanchor[ik.hip_ids[i]])) for i in (0, 1)]
    causes = _causes(ik, q, reach)
    if causes and causes[0][0] is not None and (ratios[causes[0][0]] > 1 or ratios.max() <= 1):
        task = causes[0][0]
    if not causes:
        side = task - 1 if task else int(np.argmax(reach))
        where = f"{SIDES[side]} hip-to-sole distance {reach[side]:.3f} m"
        causes.append((None, f"{failure or 'no converged solution'} ({where}, leg length {ik.robot.leg_length:.3f} m)"))
    cause = "; ".join(c for _, c in causes)
    miss = err[0] if task == 0 else max(err[task], 0.0)
    rot = err[2 + task] if task else 0.0
    return IKInfeasibleError(
        f"whole-body IK infeasible for {ik.robot.name} at t = {t:.3f} s: task '{TASKS[task]}' misses "
        f"its target by {miss * 1e3:.1f} mm" + (f" / {rot:.3f} rad" if task else "") + f": {cause}",
        time=t,
        task=TASKS[task],
        cause=cause,
    )


def check_velocities(ik: WholeBodyIK, t: np.ndarray, qvel: np.ndarray) -> None:
    """Raise :class:`IKInfeasibleError` (task ``joint velocity``) when a joint speed of ``qvel`` (N, nv)
    at times ``t`` (N,) is not finite or exceeds the robot's ``velocity_limits`` (rad/s)."""
    vj = np.abs(qvel[:, ik.vadr])
    name = ik.robot.name
    if not np.all(np.isfinite(vj)):
        k = int(np.argmax(~np.all(np.isfinite(vj), axis=1)))
        raise IKInfeasibleError(
            f"whole-body IK infeasible for {name} at t = {t[k]:.3f} s: task 'joint velocity' is not finite",
            time=float(t[k]),
            task="joint velocity",
            cause="non-finite velocity",
        )
    over = vj / ik.robot.velocity_limit
    if np.any(over > 1.0):
        k, j = (int(x) for x in np.unravel_index(int(np.argmax(over)), over.shape))
        cause = f"{ik.robot.joint_names[j]} at {vj[k, j]:.2f} rad/s > limit {ik.robot.velocity_limit[j]:.2f} rad/s"
        raise IKInfeasibleError(
            f"whole-body IK infeasible for {name} at t = {t[k]:.3f} s: task 'joint velocity' exceeds the "
            f"velocity limit: {cause}",
            time=float(t[k]),
            task="joint velocity",
            cause=cause,
        )
