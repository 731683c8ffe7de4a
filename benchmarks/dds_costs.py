"""Cost of the hg protocol's pieces (docs/deploy.md), against the official SDK's CRC in the same run.

    .venv/bin/python benchmarks/dds_costs.py [--repeats 2000] [--json out.json]

Per call, timed with ``time.perf_counter`` after warm-up calls, median and p99 (us):

* ``lowcmd_crc``: gaitshift's CRC of a ``LowCmd_`` (the SDK's packing with ``struct`` and CRC-32/MPEG-2
  through zlib, :mod:`gaitshift.dds.crc`), and the baseline: the SDK's ``CRC().Crc(msg)`` on its own
  ``LowCmd_`` with its pure-Python routine (the wheel ``unitree-sdk2==1.0.1`` in ``.venv/oracle``: the
  compiled library its Linux branch loads is not in the wheel);
* ``lowstate_crc`` likewise for a ``LowState_``;
* the conversions (``lowcmd_from_command`` with the CRC, ``frame_from_lowstate`` with the CRC check) and
  cyclonedds's ``serialize`` / ``deserialize`` of both messages: the rest of a control period's
  protocol work;
* gaitshift's own topics' per-tick work in the brain: the estimate (``estimate_message`` and its
  ``serialize``, what a ``DataWriter.write`` does to it), a live command's check (``check_command``), and
  the gyro calibration of a 2 s hold, once at its end (``LegRate.samples`` of :mod:`gaitshift.dds.still_gyro`).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from collections.abc import Callable
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
import unitree_oracle
from gaitshift.control.frames import MotorCommand, SensorFrame
from gaitshift.dds import messages
from gaitshift.dds.cmdvel import CommandLimits, check_command
from gaitshift.dds.convert import (
    frame_from_lowstate,
    lowcmd_from_command,
    lowstate_from_frame,
)
from gaitshift.dds.crc import lowcmd_crc, lowstate_crc
from gaitshift.dds.diagnostics import estimate_message
from gaitshift.dds.own_messages import VelocityCommand_
from gaitshift.dds.still_gyro import LegRate
from gaitshift.robots.config import load_robot
from gaitshift.robots.model import robot_model


def timed(fn: Callable[[], Any], repeats: int, warmup: int = 3) -> dict[str, float]:
    """Median and p99 of ``repeats`` calls of ``fn``, us."""
    for _ in range(warmup):
        fn()
    t = np.empty(repeats)
    for i in range(repeats):
        t0 = time.perf_counter()
        fn()
        t[i] = time.perf_counter() - t0
    return {"median_us": float(np.median(t) * 1e6), "p99_us": float(np.percentile(t, 99) * 1e6), "n": repeats}


def own_topics(frame: SensorFrame, repeats: int) -> dict[str, dict[str, float]]:
    """The brain's per-tick work on gaitshift's own topics (module docstring)."""
    model = robot_model(load_robot("g1"), 0.002)
    legs = LegRate(model.model, model.imu_site, tuple(model.robot.sole_bodies), model.motor_names)
    est = SimpleNamespace(qpos=np.r_[0, 0, 0.75, 1, 0, 0, 0, frame.q], qvel=np.zeros(35), contact=np.ones(2, bool))
    limits, cmd = CommandLimits(1.0, 0.5, 0.3, 1.0), VelocityCommand_(vx=0.4, yaw_rate=0.2)
    hold = (0.002 * np.arange(1000), np.tile(frame.imu_gyro, (1000, 1)), np.tile(frame.q, (1000, 1)))
    return {
        "Estimate_ (built + serialize)": timed(
            lambda: estimate_message(7, 0.1, "locomotion", est).serialize(), repeats
        ),
        "check_command (VelocityCommand_)": timed(lambda: check_command(cmd, limits), repeats),
        "LegRate.samples (a 2 s hold, once)": timed(lambda: legs.samples(*hold), max(1, repeats // 100)),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=2000)
    ap.add_argument("--json", default=None)
    args = ap.parse_args()
    oracle = unitree_oracle.load()
    if oracle is None:
        raise SystemExit(unitree_oracle.SKIP_REASON)
    rng = np.random.default_rng(0)
    cmd_fields, state_fields = unitree_oracle.lowcmd_fields(rng), unitree_oracle.lowstate_fields(rng)
    ours_cmd = unitree_oracle.build_lowcmd(messages, cmd_fields)
    sdk_cmd = unitree_oracle.build_lowcmd(oracle.hg, cmd_fields)
    ours_state = unitree_oracle.build_lowstate(messages, state_fields)
    sdk_state = unitree_oracle.build_lowstate(oracle.hg, state_fields)
    n = 29
    command = MotorCommand(
        q=rng.normal(size=n), dq=rng.normal(size=n), kp=np.full(n, 50.0), kd=np.ones(n), tau=rng.normal(size=n)
    )
    frame = SensorFrame(
        t=0.0,
        imu_quat=np.array([1.0, 0, 0, 0]),
        imu_gyro=rng.normal(size=3),
        imu_acc=rng.normal(size=3),
        q=rng.normal(size=n),
        dq=rng.normal(size=n),
        tau_est=rng.normal(size=n),
    )
    state = lowstate_from_frame(frame, 1, 5)
    cmd_bytes, state_bytes = lowcmd_from_command(command, 5).serialize(), state.serialize()
    few = max(20, args.repeats // 20)  # the pure-Python baselines take milliseconds each
    rows = {
        "lowcmd_crc": timed(lambda: lowcmd_crc(ours_cmd), args.repeats),
        "lowcmd_crc sdk (baseline)": timed(lambda: oracle.crc(sdk_cmd), few, warmup=1),
        "lowstate_crc": timed(lambda: lowstate_crc(ours_state), args.repeats),
        "lowstate_crc sdk (baseline)": timed(lambda: oracle.crc(sdk_state), few, warmup=1),
        "lowcmd_from_command (with CRC)": timed(lambda: lowcmd_from_command(command, 5), args.repeats // 4),
        "frame_from_lowstate (CRC checked)": timed(lambda: frame_from_lowstate(state, 0.0, n), args.repeats // 4),
        "lowstate_from_frame (with CRC)": timed(lambda: lowstate_from_frame(frame, 1, 5), args.repeats // 4),
        "LowCmd_.serialize": timed(ours_cmd.serialize, few),
        "LowCmd_.deserialize": timed(lambda: messages.LowCmd_.deserialize(cmd_bytes), few),
        "LowState_.serialize": timed(state.serialize, few),
        "LowState_.deserialize": timed(lambda: messages.LowState_.deserialize(state_bytes), few),
        **own_topics(frame, args.repeats // 4),
    }
    utc = time.strftime("%Y-%m-%d %H:%M", time.gmtime())
    print(f"load average {os.getloadavg()[0]:.2f}, {os.cpu_count()} cores, UTC {utc}")
    for name, r in rows.items():
        print(f"{name:36s} median {r['median_us']:9.1f} us   p99 {r['p99_us']:9.1f} us   (n={r['n']})")
    ratio = rows["lowcmd_crc sdk (baseline)"]["median_us"] / rows["lowcmd_crc"]["median_us"]
    print(f"LowCmd_ CRC: {ratio:.0f}x faster than the SDK's pure-Python routine (medians)")
    if args.json:
        Path(args.json).write_text(json.dumps({"rows": rows, "load": os.getloadavg()[0]}, indent=2))


if __name__ == "__main__":
    main()
