"""Where a brain tick's time goes (docs/deploy.md, "Real time"): the pipeline of ``gaitshift dds control``
run in one process on gaitshift's MuJoCo world, the DDS transport replaced by cyclonedds's own
``serialize`` / ``deserialize`` of the messages (what a DataWriter and a DataReader do to them).

    PYTHONPATH=src .venv/bin/python benchmarks/brain_ticks.py [SCENARIO] [--replan MODE] [--wire W] [--json out.json]

After the warm-up (:mod:`gaitshift.dds.warmup`), every tick of the safety phases and of the locomotion
until the plan ends is timed per stage with ``time.perf_counter``: ``deserialize`` (LowState_),
``frame`` (``frame_from_lowstate``, the CRC checked), ``safety`` (``Safety.step``), ``controller``
(``Controller.tick``: re-plan ticks apart), ``guard``, ``command`` (``lowcmd_from_command``, the CRC
set), ``serialize`` (LowCmd_); and ``total``, their sum. Percentiles in ms, the count over 2 ms.
``--replan`` (inline, thread, process; default process as ``gaitshift dds control``): where the controller
re-plans (:mod:`gaitshift.control.replanner`); a background mode also reports ``plan_lag``, the ticks
each new plan came after the tick it was due at. ``--wire`` (cdr, cyclonedds; default cdr as the brain):
the messages read and written as their bytes (:mod:`gaitshift.dds.cdr`: ``deserialize`` is
``StateBytes(data)``, ``command`` is ``lowcmd_bytes``, which serializes too: ``serialize`` is 0) or by
cyclonedds's ``deserialize`` / ``serialize``.
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace

import numpy as np

from gaitshift.dds.brain import BrainOptions
from gaitshift.dds.brain_setup import build_controller
from gaitshift.dds.cdr import StateBytes
from gaitshift.dds.convert import frame_from_lowstate, lowcmd_bytes, lowcmd_from_command, lowstate_from_frame
from gaitshift.dds.gravity import standing_torques
from gaitshift.dds.messages import LowState_
from gaitshift.dds.safety import Limits, Safety, SafetySettings, standup_gains
from gaitshift.dds.warmup import warm_up
from gaitshift.robots.model import standing_qpos
from gaitshift.sim.loop import SimOptions
from gaitshift.sim.plant import build_plant
from gaitshift.sim.world import World

STAGES = ("deserialize", "frame", "safety", "controller", "guard", "command", "serialize")


def machine(ctrl, standup_time):
    cfg, model = ctrl.robot.robot, ctrl.robot.model
    limits = Limits.of_robot(
        cfg.joint_names, cfg.joint_range, cfg.speed_limits()[0], cfg.torque_limit, ctrl.motor_names
    )
    kp, kd = standup_gains(limits.tau_max)
    tau = standing_torques(ctrl.robot, ctrl.initial_qpos())
    settings = SafetySettings(kp, kd, tau, damping_time=0.1, standup_time=standup_time)
    adr = [int(model.joint(n).qposadr[0]) for n in ctrl.motor_names]
    return Safety(limits, settings, ctrl.initial_qpos()[adr])


def run(scenario, standup_time, replan="process", wire="cdr"):
    opts = BrainOptions(scenario, replan=replan, lockstep=True)  # the world applies each command at once
    ctrl = build_controller(opts)
    warm_up(build_controller(replace(opts, replan="inline")))
    saf = machine(ctrl, standup_time)
    plant = build_plant(ctrl.period, "g1")
    world = World(plant, standing_qpos(plant), SimOptions(control_period=ctrl.period, noise="none"), False, 1)
    rows, kinds = [], []
    for k in range(100000):
        world.observe(k)
        data = lowstate_from_frame(world.sense(k), k, 0).serialize()
        t, times, kind = k * ctrl.period, [time.perf_counter()], 0
        msg = StateBytes(data) if wire == "cdr" else LowState_.deserialize(data)
        times.append(time.perf_counter())
        frame = frame_from_lowstate(msg, t, len(ctrl.motor_names))
        times.append(time.perf_counter())
        cmd = saf.step(t, frame, 0.0)
        times.append(time.perf_counter())
        if cmd is None:
            tl = t - saf.locomotion_start
            if ctrl.finished(tl):
                break
            before = ctrl.trajectory
            raw = ctrl.tick(replace(frame, t=tl))
            kind = 2 if ctrl.trajectory is not before else 1
            times.append(time.perf_counter())
            cmd = saf.guard(raw, frame, t)
        else:
            times.append(times[-1])
        times.append(time.perf_counter())
        if wire == "cdr":
            lowcmd_bytes(cmd, msg.mode_machine)
            times.append(time.perf_counter())
        else:
            out = lowcmd_from_command(cmd, msg.mode_machine)
            times.append(time.perf_counter())
            out.serialize()
        times.append(time.perf_counter())
        rows.append(np.diff(times))
        kinds.append(kind)
        world.apply(cmd, k)
        world.step()
    lags = np.asarray(getattr(ctrl.replan, "lags", []), float)
    ctrl.replan.close()
    return np.array(rows) * 1e3, np.array(kinds), f"{saf.phase}: {saf.reason}", lags


def stats(a):
    return {
        "p50": float(np.percentile(a, 50)),
        "p99": float(np.percentile(a, 99)),
        "p99.9": float(np.percentile(a, 99.9)),
        "max": float(a.max()),
        "over_2ms": int((a > 2.0).sum()),
    }


def main():
    p = argparse.ArgumentParser()
    p.add_argument("scenario", nargs="?", default="g1-walk")
    p.add_argument("--standup-time", type=float, default=2.0)
    p.add_argument("--replan", choices=("inline", "thread", "process"), default="process")
    p.add_argument("--wire", choices=("cdr", "cyclonedds"), default="cdr")
    p.add_argument("--json")
    a = p.parse_args()
    ms, kinds, phase, lags = run(a.scenario, a.standup_time, a.replan, a.wire)
    total = ms.sum(axis=1)
    out = {"ticks": len(total), "phase": phase, "replan": a.replan, "wire": a.wire, "total": stats(total)}
    out |= {s: stats(ms[:, i]) for i, s in enumerate(STAGES)}
    out["controller_replan"] = stats(ms[kinds == 2, 3]) | {"ticks": int((kinds == 2).sum())}
    out["controller_other"] = stats(ms[kinds == 1, 3]) | {"ticks": int((kinds == 1).sum())}
    out["total_safety_phases"] = stats(total[kinds == 0])
    out["total_locomotion"] = stats(total[kinds > 0])
    if len(lags):
        out["plan_lag"] = {"p50": float(np.median(lags)), "max": float(lags.max()), "plans": len(lags)}
    for k, v in out.items():
        print(k, v if not isinstance(v, dict) else {n: round(x, 3) for n, x in v.items()})
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=2)


if __name__ == "__main__":
    main()
