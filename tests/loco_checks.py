"""Helpers of the locomotion tests: G1-sized plans from command scripts, a short G1 walk, and the stride-mean velocity
computed independently from the file arrays (docs/locomotion.md, "Speed semantics")."""

from __future__ import annotations

import numpy as np
import yaml

import gaitshift
from gaitshift.planners.locomotion.generator import LocomotionGenerator
from gaitshift.planners.locomotion.params import params_from_scenario
from gaitshift.planners.locomotion.plan import script_of
from gaitshift.scenario.facts import RobotFacts
from gaitshift.scenario.loader import builtin_text, load_scenario
from gaitshift.scenario.locomotion import LocomotionScenario

G1 = RobotFacts("g1", 33.34, 0.6333, 0.6922, (0.18, 0.07), 0.237)


def short_g1_walk(steps: int = 3):
    """The built-in g1-walk cut to ``steps`` steps (one accelerating, one decelerating), planned."""
    data = yaml.safe_load(builtin_text("g1-walk"))
    data["gait"] = [{"gait": "walk", "steps": steps}]
    data["profile"] = dict(data["profile"], accelerate_steps=1, decelerate_steps=1)
    data["name"] = f"g1-walk-{steps}"
    return gaitshift.plan(load_scenario(data))


def scenario(**kw):
    """A locomotion scenario from keyword fields (commands as dicts)."""
    return LocomotionScenario.model_validate({"planner": "locomotion", **kw})


def plan(commands, stop_at, facts=G1, **kw):
    """Run a command script through the generator; returns (generator, file dict of arrays)."""
    sc = scenario(commands=commands, stop_at=stop_at, **kw)
    gen = LocomotionGenerator(params_from_scenario(sc, facts))
    script_of(sc).run(gen, max_time=stop_at + 60.0)
    tr = gen.trajectory()
    d = {**tr.arrays(), "meta": tr.meta}
    return gen, d


def ss_starts(d):
    """Sample indices where a single support begins (the step boundaries of the file)."""
    ph = d["phase"]
    return np.flatnonzero((ph[1:] == 1) & (ph[:-1] != 1)) + 1


def stride_means(d):
    """Stride-mean velocities (heading frame at the stride's middle) for every window of two
    consecutive steps: list of (start index, end index, (vx, vy))."""
    s = ss_starts(d)
    out = []
    for a, b in zip(s[:-2], s[2:], strict=True):
        disp = d["com_pos"][b, :2] - d["com_pos"][a, :2]
        psi = 0.5 * (d["heading"][a] + d["heading"][b])
        c, sn = np.cos(psi), np.sin(psi)
        v = np.array([c * disp[0] + sn * disp[1], -sn * disp[0] + c * disp[1]]) / (d["t"][b] - d["t"][a])
        out.append((a, b, v))
    return out
