"""Sole pitch references on terrain (issue 13): in contact the ramp's inclination under the foothold,
in a swing a smooth blend between the two, zero on flat ground and on stairs."""

from __future__ import annotations

import numpy as np

from gaitshift.api import plan
from gaitshift.control.plan_samples import PlanSamples
from gaitshift.scenario import load_scenario
from gaitshift.scenario.terrain import terrain_of


def test_stance_soles_take_the_pitch_of_the_ramp_under_them():
    sc = load_scenario("g1-slope-up")
    traj = plan(sc)
    ps = PlanSamples.from_trajectory(traj)
    ground = terrain_of(sc.terrain)
    on = traj.contact
    want = np.arctan(ground.slope(traj.foot_pos[..., 0]))
    assert np.allclose(ps.foot_pitch[on], want[on], atol=1e-12)
    assert np.isclose(np.max(ps.foot_pitch), np.radians(10.0), atol=1e-6)  # the 10 degree ramp
    assert np.max(np.abs(np.diff(ps.foot_pitch, axis=0))) < 0.01  # blended in the swings, no jump


def test_flat_ground_and_stairs_keep_the_soles_level():
    for name in ("g1-walk", "g1-stairs-up"):
        ps = PlanSamples.from_trajectory(plan(load_scenario(name)))
        assert not np.any(ps.foot_pitch)
