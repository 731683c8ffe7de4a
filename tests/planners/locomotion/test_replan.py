"""Re-planning from a measured CoM state: the generator restarts the horizontal CoM from the
measurement, re-targets the feet still in the air (their references stay continuous), keeps eq. (1)
at every sample, and is back on the commanded stride speed from the second full stride after."""

from __future__ import annotations

import numpy as np

import physics
from gaitshift.planners.locomotion.generator import LocomotionGenerator
from gaitshift.planners.locomotion.params import params_from_scenario
from loco_checks import G1, scenario, ss_starts, stride_means


def _run(v, gait, push_at, push):
    gen = LocomotionGenerator(params_from_scenario(scenario(gait=gait), G1))
    gen.command(v, 0.0, 0.0)
    gen.advance(round(push_at / gen.dt))
    p = gen.tick()
    com, vel = p.com_pos[0].copy(), p.com_vel[0].copy()
    gen.replan(com[:2] + push[:2], vel[:2] + push[2:])
    gen.advance(round(6.0 / gen.dt))
    gen.stop()
    while not gen.finished:
        gen.step()
    tr = gen.trajectory()
    return gen, {**tr.arrays(), "meta": tr.meta}


def test_replan_mid_swing_keeps_the_physics_and_recovers_the_speed():
    gen, d = _run(0.6, "walk", 3.1, np.array([0.03, -0.02, 0.10, 0.15]))
    i = round(3.101 / gen.dt)
    assert physics.eq1_error(d, 9.81) < 1e-9
    # the CoM restarts at the measured state (a jump of the push), the feet do not jump
    assert np.linalg.norm(d["com_pos"][i, :2] - d["com_pos"][i - 1, :2]) > 0.02
    feet_jump = np.max(np.abs(np.diff(d["foot_pos"], axis=0)))
    assert feet_jump < 2 * gen.dt * 3.0  # < 3 m/s foot speed
    assert any(e.kind == "replan" for e in gen.events)
    s = ss_starts(d)
    after = s[d["t"][s] > 3.1]
    wins = [w for w in stride_means(d) if after[2] <= w[0] and d["t"][w[1]] < 9.0]
    assert wins
    for a, _, v in wins:
        assert abs(v[0] - 0.6) < 1e-3 and abs(v[1]) < 1e-3, (d["t"][a], v)


def test_replan_in_flight_retargets_the_landing_foot():
    gen, d = _run(1.6, "run", 4.0, np.array([0.0, 0.0, 0.0, 0.25]))
    i = round(4.001 / gen.dt)
    assert d["phase"][i] in (1, 2)
    assert physics.eq1_error(d, 9.81) < 1e-9 and physics.flight_error(d, 9.81) < 1e-12
    s = ss_starts(d)
    after = s[d["t"][s] > 4.0]
    wins = [w for w in stride_means(d) if after[2] <= w[0] and d["t"][w[1]] < 10.0]
    assert wins
    for a, _, v in wins:
        assert abs(v[0] - 1.6) < 1e-3 and abs(v[1]) < 1e-3, (d["t"][a], v)
