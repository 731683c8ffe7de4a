"""The columns of the locomotion generator's sample blocks and their assembly into the trajectory file."""

from __future__ import annotations

from typing import Any

import numpy as np

from gaitshift.planners.locomotion.steps import STEP_CODES
from gaitshift.planners.streaming.samples import Samples
from gaitshift.trajectory.contract import Trajectory

__all__ = ["FIELDS", "locomotion_meta", "trajectory_from"]

#: per-sample fields: name -> (trailing shape, dtype)
FIELDS: dict[str, tuple[tuple[int, ...], Any]] = {
    "com_pos": ((3,), np.float64),
    "com_vel": ((3,), np.float64),
    "com_acc": ((3,), np.float64),
    "zmp": ((3,), np.float64),
    "phase": ((), np.int8),
    "contact": ((2,), np.bool_),
    "stiffness": ((), np.float64),
    "foot_pos": ((2, 3), np.float64),
    "foot_yaw": ((2,), np.float64),
    "foot_vel": ((2, 4), np.float64),
    "foot_acc": ((2, 4), np.float64),
    "heading": ((), np.float64),
    "gait": ((), np.int8),
    "step": ((), np.int32),
    "step_type": ((), np.int8),
}


def trajectory_from(
    s: Samples,
    footsteps: list[tuple[float, float, float, float, int]],
    bounds: list[int],
    meta: dict[str, Any],
) -> Trajectory:
    """The trajectory file of the emitted samples ``s`` (planner "locomotion"; the run's samples from
    ``s.t[0]`` on): the footholds landed on (x, y, z, yaw, side), the phase boundaries (the run's sample
    indices) and the ``meta`` to write."""
    cols, cmd, t = s.cols, s.command, s.t
    dt = float(meta.get("dt", t[1] - t[0] if len(t) > 1 else 0.0))  # the planner's step: exact far into a run
    fs = np.array([f[:4] for f in footsteps], dtype=np.float64)
    side = np.array([f[4] for f in footsteps], dtype=np.int8)
    meta = {**meta, "step_types": {str(code): name for name, code in STEP_CODES.items()} | {"-1": "standing"}}
    first = round(float(t[0]) / dt) if dt > 0 else 0  # a window of the run (gaitshift.trajectory.window)
    end = first + len(t)
    bt = np.array([b for b in bounds if first <= b < end] + [end - 1], dtype=np.float64) * dt
    extras = {"step_index": cols["step"], "boundary_t": bt, "step_type": cols["step_type"]}
    return Trajectory(
        t=t,
        com_pos=cols["com_pos"],
        com_vel=cols["com_vel"],
        com_acc=cols["com_acc"],
        zmp=cols["zmp"],
        phase=cols["phase"],
        contact=cols["contact"],
        foot_pos=cols["foot_pos"],
        stiffness=cols["stiffness"],
        footsteps=fs,
        footstep_side=side,
        command_vel=cmd[:, :2].copy(),
        heading=cols["heading"],
        foot_yaw=cols["foot_yaw"],
        gait=cols["gait"],
        command_yaw_rate=cmd[:, 2].copy(),
        meta=meta,
        extras=extras,
    )


def locomotion_meta(p: Any, stiffness: dict[str, float], events: list[dict[str, Any]]) -> dict[str, Any]:
    """The ``meta`` of a locomotion trajectory: the parameters that shaped it (``p``, a
    :class:`~.params.LocomotionParams`), the stiffness values and the events."""
    tm = p.timing
    return {
        "planner": "locomotion",
        "gravity": p.gravity,
        "foot_size": list(p.foot_size),
        "dt": p.dt,
        "height": p.height,
        "step_width": p.step_width,
        "gait_mode": p.gait,
        "switch": {"walk_to_run": p.walk_to_run, "run_to_walk": p.run_to_walk},
        "timing": {
            "walk_single": tm.walk_single,
            "double": tm.double,
            "run_single": tm.run_single,
            "flight": tm.flight,
            "start": tm.start,
            "stop": tm.stop,
        },
        "stiffness": stiffness,
        "events": events,
        "command_frame": "heading",
        "velocity_convention": "analytic (eqs. (3)-(6) of paper 001)",
    }
