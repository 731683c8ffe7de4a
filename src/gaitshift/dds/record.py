"""A run's recording, one row per tick: ``gaitshift dds control --record`` and ``gaitshift dds robot --record``.

The two processes record apart, and the robot's tick ties the files together: the brain's row carries the
``tick`` of the ``LowState_`` it acted on, the robot's row the tick it stepped. With both files, the
estimate the brain acted on can be set against the truth the robot kept (the truth never reaches the brain;
the files meet only afterwards, in the hands of whoever reads them).

Brain (:data:`BRAIN_COLUMNS`, ``n`` motors; nq, nv of the controller's model)::

    t            s, the machine's clock of the tick          tick        LowState_.tick acted on
    duration     s, the tick's wall time                     missed      1: longer than a period
    fresh        1: a state of a new tick came               kind        0 safety, 1 controller, 2 re-plan
    phase        index in PHASES                             estimated   1: the controller ticked
    q, dq, tau_est   (n,) rad, rad/s, N m as the state reported them
    quat (4,) w x y z, gyro (3,) rad/s, acc (3,) m/s^2: the IMU as reported
    cmd_q, cmd_dq, cmd_kp, cmd_kd, cmd_tau  (n,) the command written (after the safety's clamps)
    est_qpos (nq,), est_qvel (nv,), est_contact (2,): the controller's estimate (zeros when not estimated)
    ref_com, ref_com_vel (3,), ref_stance (2,), ref_foot (6,: the soles' (2, 3)): what the controller
                 tracked at the tick, in its estimate's frame (zeros when it did not tick)

Robot (:data:`ROBOT_COLUMNS`)::

    t            s of simulated time (tick x period)         tick        the tick stepped
    applied      0 held in the gantry (the command's columns zero), 1 a command, 2 damping
    qpos (nq,), qvel (nv,): the truth before the step       touching (2,), grf (6,) N: the soles' (2, 3) forces
    cmd_q, cmd_dq, cmd_kp, cmd_kd, cmd_tau  (n,) the command applied

:func:`meet` pairs the brain's rows with the robot's. Every value is finite (the error contract: no NaN
in any output); the file is written once, at the end (also after SIGINT/SIGTERM), through a temporary
file: never partial. Both files hold ``meta`` (JSON): the column names, the robot, the period.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from gaitshift.common.atomic import atomic_path, check_suffix
from gaitshift.dds.safety import PHASES

__all__ = [
    "BLOCK",
    "BRAIN_COLUMNS",
    "ROBOT_COLUMNS",
    "Recorder",
    "brain_row",
    "brain_widths",
    "check_record",
    "command_values",
    "meet",
    "robot_widths",
]

#: the brain's columns: name -> width in units of (n motors, nq, nv); (0, 0, 0, k): k values
BRAIN_COLUMNS: dict[str, tuple[int, int, int, int]] = {
    "t": (0, 0, 0, 1),
    "tick": (0, 0, 0, 1),
    "duration": (0, 0, 0, 1),
    "missed": (0, 0, 0, 1),
    "fresh": (0, 0, 0, 1),
    "kind": (0, 0, 0, 1),
    "phase": (0, 0, 0, 1),
    "estimated": (0, 0, 0, 1),
    "q": (1, 0, 0, 0),
    "dq": (1, 0, 0, 0),
    "tau_est": (1, 0, 0, 0),
    "quat": (0, 0, 0, 4),
    "gyro": (0, 0, 0, 3),
    "acc": (0, 0, 0, 3),
    "cmd_q": (1, 0, 0, 0),
    "cmd_dq": (1, 0, 0, 0),
    "cmd_kp": (1, 0, 0, 0),
    "cmd_kd": (1, 0, 0, 0),
    "cmd_tau": (1, 0, 0, 0),
    "est_qpos": (0, 1, 0, 0),
    "est_qvel": (0, 0, 1, 0),
    "est_contact": (0, 0, 0, 2),
    "ref_com": (0, 0, 0, 3),
    "ref_com_vel": (0, 0, 0, 3),
    "ref_stance": (0, 0, 0, 2),
    "ref_foot": (0, 0, 0, 6),
}

#: the robot's columns, as :data:`BRAIN_COLUMNS`
ROBOT_COLUMNS: dict[str, tuple[int, int, int, int]] = {
    "t": (0, 0, 0, 1),
    "tick": (0, 0, 0, 1),
    "applied": (0, 0, 0, 1),
    "qpos": (0, 1, 0, 0),
    "qvel": (0, 0, 1, 0),
    "touching": (0, 0, 0, 2),
    "grf": (0, 0, 0, 6),
    "cmd_q": (1, 0, 0, 0),
    "cmd_dq": (1, 0, 0, 0),
    "cmd_kp": (1, 0, 0, 0),
    "cmd_kd": (1, 0, 0, 0),
    "cmd_tau": (1, 0, 0, 0),
}


#: rows per block of a :class:`Recorder` (a brain's row of the G1 is 2.7 kB: 11 MB a block, 1.35 MB/s at 500 Hz)
BLOCK = 4096


def check_record(path: object) -> None:
    """``--record``: None, or a path (str or Path) whose name ends in ``.npz``; else :class:`InputError`."""
    if path is not None:
        check_suffix(path, "--record", (".npz",))


def _widths(columns: dict[str, tuple[int, int, int, int]], n: int, nq: int, nv: int) -> dict[str, int]:
    return {name: a * n + b * nq + c * nv + k for name, (a, b, c, k) in columns.items()}


def brain_widths(n: int, nq: int, nv: int) -> dict[str, int]:
    """The width of each of the brain's columns for ``n`` motors and a model of ``nq``, ``nv``."""
    return _widths(BRAIN_COLUMNS, n, nq, nv)


def robot_widths(n: int, nq: int, nv: int) -> dict[str, int]:
    """The width of each of the robot's columns."""
    return _widths(ROBOT_COLUMNS, n, nq, nv)


class Recorder:
    """Rows of fixed-width float columns, one per tick, kept in blocks of :data:`BLOCK` rows (a row costs a
    few copies; a new block is one lazily zeroed allocation, never a copy of the rows so far, so no tick of
    a real-time loop waits for the recording to grow), saved as one ``.npz`` (one array per column, (rows,)
    or (rows, width)).

    Args:
        path: the ``.npz`` to write at :meth:`save`. widths: column name -> values per row.
        meta: what the file says of itself (JSON-able), beside the column names.
    """

    def __init__(self, path: str | Path, widths: dict[str, int], meta: dict[str, Any]) -> None:
        self.path, self.widths, self.meta = Path(path), dict(widths), dict(meta)
        self.rows = 0
        self._blocks: list[dict[str, np.ndarray]] = []

    def add(self, **values: Any) -> None:
        """Append one row; a column not given is zeros."""
        i = self.rows % BLOCK
        if i == 0:
            self._blocks.append({name: np.zeros((BLOCK, w)) for name, w in self.widths.items()})
        block = self._blocks[-1]
        for name, v in values.items():
            block[name][i] = v
        self.rows += 1

    def arrays(self) -> dict[str, np.ndarray]:
        """The columns so far: (rows,) for width 1, else (rows, width)."""
        out = {}
        for name, w in self.widths.items():
            a = np.concatenate([b[name] for b in self._blocks])[: self.rows] if self._blocks else np.zeros((0, w))
            out[name] = a[:, 0] if w == 1 else a
        return out

    def save(self) -> None:
        """Write the file (through a temporary file; ValueError on a value that is not finite)."""
        arrays: dict[str, Any] = self.arrays()
        bad = [name for name, a in arrays.items() if not np.all(np.isfinite(a))]
        if bad:
            raise ValueError(f"not finite in the recording's columns {bad}")
        meta = json.dumps({**self.meta, "columns": list(self.widths), "rows": self.rows, "phases": list(PHASES)})
        with atomic_path(self.path, "--record") as tmp:
            np.savez(tmp, meta=np.array(meta), **arrays)


def command_values(cmd: Any) -> dict[str, np.ndarray]:
    """The ``cmd_*`` columns of a :class:`~gaitshift.control.frames.MotorCommand`."""
    return {"cmd_q": cmd.q, "cmd_dq": cmd.dq, "cmd_kp": cmd.kp, "cmd_kd": cmd.kd, "cmd_tau": cmd.tau}


def brain_row(tick: int, frame: Any, cmd: Any, record: Any, **scalars: float) -> dict[str, Any]:
    """One brain row: the state's ``tick``, the ``frame`` it became (None: out of range, zeros), the command
    written, the controller's tick (a :class:`~gaitshift.control.controller.TickRecord`, or None: it did not
    tick), and the scalar columns (t, duration, missed, fresh, kind, phase)."""
    row: dict[str, Any] = {"tick": tick, **scalars, **command_values(cmd)}
    if frame is not None:
        row |= {"q": frame.q, "dq": frame.dq, "tau_est": frame.tau_est}
        row |= {"quat": frame.imu_quat, "gyro": frame.imu_gyro, "acc": frame.imu_acc}
    if record is None:
        return row
    ref = record.reference
    row |= {
        "ref_com": ref.com_pos,
        "ref_com_vel": ref.com_vel,
        "ref_stance": ref.stance,
        "ref_foot": ref.foot_pos.ravel(),
    }
    est = record.estimate
    if est is not None:
        row |= {"estimated": 1, "est_qpos": est.qpos, "est_qvel": est.qvel, "est_contact": est.contact}
    return row


def meet(brain: Any, robot: Any) -> np.ndarray:
    """For each of the brain's rows, the row of the robot's recording of the same tick (-1: none, a tick
    the robot's file does not hold). ``brain`` and ``robot``: the two loaded files (``np.load``)."""
    ticks = np.asarray(robot["tick"], np.int64)
    order = np.argsort(ticks)
    wanted = np.asarray(brain["tick"], np.int64)
    at = np.clip(np.searchsorted(ticks[order], wanted), 0, len(ticks) - 1)
    rows: np.ndarray = np.where(ticks[order][at] == wanted, order[at], -1)
    return rows
