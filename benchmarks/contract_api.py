"""The Python API surface of the contract sample: random arguments to the public functions of
``gaitshift.__all__`` that take user values (benchmarks/contract_sample.py).

A call ends in a result (checked: no NaN where the API promises numbers) or a ``GaitshiftError`` whose
message is one line (an ``InputError`` naming an argument). Calls that would run a simulation or
build a controller get arguments that must be refused.
"""

from __future__ import annotations

import contextlib
import functools
import math
import random
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

import gaitshift
from contract_cases import LOCOMOTION, TVLIP, VHIP, Base, Case
from contract_mutate import garbage, mutate


def _arg(rng: random.Random, valid: Any) -> Any:
    """``valid`` half the time, else a hostile value (a number of any size, a text, None, a list...)."""
    return valid if rng.random() < 0.5 else garbage(rng)


def _vec(rng: random.Random, valid: list[float]) -> Any:
    if rng.random() < 0.5:
        return valid
    return rng.choice([garbage(rng), [garbage(rng) for _ in valid], [rng.choice([1e300, -1e5, math.inf]), 0.0]])


def finite(*values: Any) -> bool:
    """Every number in ``values`` (arrays, sequences, floats) is finite."""
    return all(bool(np.all(np.isfinite(np.asarray(v, dtype=float)))) for v in values)


@functools.cache
def _replanner_scenario() -> Any:
    return gaitshift.load_scenario(TVLIP)


@functools.cache
def _loco_scenario() -> Any:
    return gaitshift.load_scenario(LOCOMOTION)


def _stiffness(rng: random.Random, base: Base) -> tuple[Callable[[], Any], set[str]]:
    args = [_arg(rng, v) for v in (0.95, 0.4, 0.15, 0.15)]
    kw = {"gravity": _arg(rng, 9.81)} if rng.random() < 0.3 else {}

    def call() -> bool:
        k = gaitshift.stiffness(*args, **kw)
        return finite(k.T_w, k.T_r, k.v_r, k.T_t0, k.T_t1)

    return call, {"height", "single_support", "double_support", "flight", "gravity"}


def _plan(rng: random.Random, base: Base) -> tuple[Callable[[], Any], set[str]]:
    data = rng.choice([TVLIP, VHIP, LOCOMOTION])
    doc, added = mutate(data, rng, rng.choice([0, 1, 2]))
    what = rng.choice([doc, doc, doc, garbage(rng), "nope", "g1-walk.yaml", str(base.folder / "tvlip.npz")])
    from contract_cases import SCENARIO_NAMES

    return lambda: gaitshift.plan(what) is not None, SCENARIO_NAMES | added


def _load(rng: random.Random, base: Base) -> tuple[Callable[[], Any], set[str]]:
    what = rng.choice(
        [garbage(rng), "nope", str(base.folder / "tvlip.csv"), base.folder, b"x", Path("/nonexistent.npz")]
    )
    fn = rng.choice([gaitshift.Trajectory.load, gaitshift.load_scenario])
    return lambda: fn(what) is not None, {"file", "scenario", "path", "source", "meta"}


def _replan(rng: random.Random, base: Base) -> tuple[Callable[[], Any], set[str]]:
    t = _arg(rng, rng.uniform(0.0, 3.0))
    p, v = _vec(rng, [0.2, 0.01]), _vec(rng, [0.3, 0.0])
    tq = _arg(rng, [rng.uniform(0, 3), 1.0])

    def call() -> bool:
        r = gaitshift.Replanner.from_scenario(_replanner_scenario())
        with contextlib.suppress(gaitshift.InfeasibleError):  # cannot stop at the goal: one line
            r.replan(t, p, v)
        return finite(*r.reference(tq)[:3])  # the ZMP (4th) is NaN in flight by contract

    return call, {"t", "p_xy", "v_xy"}


def _locomotion(rng: random.Random, base: Base) -> tuple[Callable[[], Any], set[str]]:
    cmd = [_arg(rng, x) for x in (rng.uniform(-0.5, 1.5), rng.uniform(-0.3, 0.3), rng.uniform(-1, 1))]
    goal = [_arg(rng, x) for x in (rng.uniform(-2, 2), rng.uniform(-2, 2), 0.5)]
    n = _arg(rng, rng.randrange(1, 400))
    how = rng.choice(["command", "goto", "both"])

    def call() -> bool:
        from gaitshift.api import robot_facts

        gen = gaitshift.LocomotionGenerator.from_scenario(_loco_scenario(), robot_facts(_loco_scenario()))
        if how in ("command", "both"):
            gen.command(*cmd)
        if how in ("goto", "both"):
            gen.goto(*goal)
        block = gen.advance(n)
        return finite(block.com_pos, block.com_vel, block.com_acc)

    return call, {"vx", "vy", "yaw_rate", "x", "y", "yaw", "n", "ticks", "command", "goto"}


def _frame(rng: random.Random, base: Base) -> tuple[Callable[[], Any], set[str]]:
    n = 29
    fields = {
        "t": _arg(rng, 0.1),
        "imu_quat": _vec(rng, [1.0, 0.0, 0.0, 0.0]),
        "imu_gyro": _vec(rng, [0.0, 0.0, 0.0]),
        "imu_acc": _vec(rng, [0.0, 0.0, 9.81]),
        "q": _arg(rng, [0.0] * n),
        "dq": _arg(rng, [0.0] * n),
        "tau_est": _arg(rng, [0.0] * n),
    }
    if rng.random() < 0.3:
        fields[rng.choice(["foot_force", "extra"])] = _vec(rng, [100.0, 100.0])
    names = {f"SensorFrame.{k}" for k in fields} | {"SensorFrame"}
    return lambda: gaitshift.SensorFrame.checked(n, **fields) is not None, names


def _simulate(rng: random.Random, base: Base) -> tuple[Callable[[], Any], set[str]]:
    """Only refusals: an unknown scenario, a wrong type, or one option outside its range."""
    bad = rng.choice(
        [
            ("scenario", rng.choice([None, 3, "nope", [1], {"planner": "nope"}])),
            ("control_period", rng.choice([-1.0, 1.0, math.nan, "x"])),
            ("state", rng.choice(["truth", 3])),
            ("noise", "loud"),
            ("friction", rng.choice([-1.0, math.inf, "x"])),
            ("mass_scale", rng.choice([0.0, -1.0, math.nan])),
            ("latency", rng.choice([-1, 10**9, 1.5])),
            ("bogus_option", 1),
        ]
    )
    scenario = bad[1] if bad[0] == "scenario" else "g1-walk"
    options = {} if bad[0] == "scenario" else {bad[0]: bad[1]}
    fn = rng.choice(["simulate", "controller"])

    def call() -> Any:
        if fn == "controller":
            return gaitshift.Controller.from_scenario(scenario, **options)
        return gaitshift.simulate(scenario, **options)

    return call, {bad[0], "scenario", "planner", "options", "settings", "SimOptions", "ControllerSettings"}


#: public functions taking user values -> case builder (call, names a refusal may use)
API_CALLS: dict[str, Callable[[random.Random, Base], tuple[Callable[[], Any], set[str]]]] = {
    "stiffness": _stiffness,
    "plan": _plan,
    "load": _load,
    "Replanner": _replan,
    "LocomotionGenerator": _locomotion,
    "SensorFrame": _frame,
    "simulate": _simulate,
}
#: functions whose calls must be refused (a result would mean a simulation ran)
MUST_REFUSE = ("simulate",)


def api_case(rng: random.Random, folder: Path, base: Base) -> Case:
    name = rng.choice(sorted(API_CALLS))
    call, names = API_CALLS[name](rng, base)
    codes = (2,) if name in MUST_REFUSE else (0, 2)
    return Case("api", names, call=call, codes=codes, note=name)
